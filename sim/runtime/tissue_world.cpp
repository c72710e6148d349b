#include "sim/runtime/tissue_world.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace lap::sim {

std::string_view to_string(ModelFaultKind kind) {
  switch (kind) {
    case ModelFaultKind::kNone:
      return "";
    case ModelFaultKind::kCatheter:
      return "catheter";
    case ModelFaultKind::kLocalDeformation:
      return "local deformation";
    case ModelFaultKind::kModalShell:
      return "modal shell";
  }
  return "unknown";
}

std::unique_ptr<TissueWorld> TissueWorld::create(std::shared_ptr<const TissueModel> model) {
  std::unique_ptr<TissueWorld> w(new TissueWorld());
  w->model_ = std::move(model);
  const TissueModel& m = *w->model_;
  const TissueWorldSettings& settings = m.settings();
  w->catheter_ = std::make_unique<models::CatheterState>(
      m.catheter_model(), settings.catheter_start_W, settings.catheter_direction_W);
  w->catheter_->fixed[0] = 1;  // where it enters: held
  const size_t particles = w->catheter_->positions.size();
  if (m.duct_organ() >= 0) {
    const haptics::TriangleMesh& wall = m.surface(m.duct_organ());
    w->duct_state_ = std::make_unique<models::ModalShellState>(*m.duct().model);
    w->duct_wall_ = std::make_unique<haptics::MeshDatabase>(haptics::MeshDatabase::build(wall));
    w->duct_scratch_ = std::make_unique<haptics::MeshUpdateScratch>(*w->duct_wall_);
    w->duct_positions_W_ = wall.positions;
    w->duct_velocities_W_.assign(wall.positions.size(), Eigen::Vector3d::Zero());
    w->duct_all_nodes_.resize(wall.positions.size());
    for (size_t v = 0; v < w->duct_all_nodes_.size(); ++v) {
      w->duct_all_nodes_[v] = static_cast<int32_t>(v);
    }
  }
  w->organ_pose_W_.assign(static_cast<size_t>(m.organ_count()), Eigen::Isometry3d::Identity());
  for (int32_t i = 0; i < m.organ_count(); ++i) {
    const OrganTissue& t = m.organ(i);
    OrganState s;
    s.contact = t.contact;  // its stiffness is the organ's (TissueModel)
    if (t.kind == TissueKind::kLocal) {
      s.local = std::make_unique<models::LocalDeformationState>(*t.local);
      s.dents.resize(particles + static_cast<size_t>(2 * ToolModelInput::kMaxContacts));
    }
    w->organs_.push_back(std::move(s));
    w->organs_.back().tracking = std::make_unique<models::SurfaceTracking>(
        w->contact_surface(i), Eigen::Isometry3d::Identity(), *w->catheter_);
    w->organs_.back().reactions.resize(particles);
  }
  return w;
}

Result<std::unique_ptr<TissueWorld>> TissueWorld::build(const Scene& scene,
                                                        const TissueWorldSettings& settings,
                                                        std::vector<std::string>* notes) {
  Result<std::shared_ptr<const TissueModel>> model = TissueModel::build(scene, settings, notes);
  if (!model.ok()) return model.diagnostics();
  return create(std::move(model).value());
}

const haptics::MeshDatabase& TissueWorld::contact_surface(int32_t organ) const {
  const OrganTissue& t = model_->organ(organ);
  return t.kind == TissueKind::kDuct ? *duct_wall_ : *t.rest;
}

ModelFault TissueWorld::step(const std::array<ToolModelInput, 2>& tools, double dt) noexcept {
  ModelFault fault;
  grasp(tools, dt);
  // 1b. The incision's rim holds the catheter where it passes through it (incision_rim.h).
  const DuctTissue& duct = model_->duct();
  if (duct.has_incision)
    models::hold_at_incision(duct.rim, model_->catheter_model(), catheter_.get());
  find_catheter_contacts();
  // 3. The catheter.
  if (injected_ == ModelFaultKind::kCatheter) {
    catheter_->velocities.back().x() = std::numeric_limits<double>::quiet_NaN();
  }
  if (!models::step_catheter(model_->catheter_model(), catheter_.get(), dt)) {
    fault = {ModelFaultKind::kCatheter, -1};
  }
  for (models::GraspState& g : catheter_grasps_) models::finish_grasp_step(*catheter_, &g);
  deepest_dent_ = 0.0;
  for (int32_t i = 0; i < static_cast<int32_t>(organs_.size()); ++i) {
    OrganState& s = organs_[static_cast<size_t>(i)];
    const std::span<models::SurfaceReaction> reactions(s.reactions.data(),
                                                       static_cast<size_t>(s.reaction_count));
    models::settle_reactions(*catheter_, reactions);
    Eigen::Vector3d push = Eigen::Vector3d::Zero();
    for (const models::SurfaceReaction& r : reactions) push += r.force_on_surface_W;
    s.catheter_push_n = push.norm();
    const TissueKind kind = model_->organ(i).kind;
    bool ok = true;
    if (kind == TissueKind::kLocal) {
      ok = dent_local_organ(i, tools, reactions);
      if (!ok && !fault) fault = {ModelFaultKind::kLocalDeformation, i};
    } else if (kind == TissueKind::kDuct) {
      ok = step_duct(i, tools, reactions, dt);
      if (!ok && !fault) fault = {ModelFaultKind::kModalShell, i};
    }
  }
  injected_ = ModelFaultKind::kNone;
  return fault;
}

void TissueWorld::grasp(const std::array<ToolModelInput, 2>& tools, double dt) noexcept {
  // 1. Grasps (their anchors are set afresh each step).
  const TissueWorldSettings& settings = model_->settings();
  const DuctTissue& duct = model_->duct();
  if (duct_state_) models::clear_node_anchors(duct_state_.get());
  models::clear_anchors(catheter_.get());
  for (size_t t = 0; t < 2; ++t) {
    squeeze_[t] = 0.0;
    duct_grasp_force_n_[t] = 0.0;
    duct_squeeze_n_[t] = 0.0;
    if (!tools[t].valid) continue;
    // Jaws that hold the duct do not also take the catheter: in the lumen they hold, it lies
    // between them too (the left hand steadying the duct, sim/authoring/expert_run.h). Jaws that
    // hold the catheter may still take the duct (duct_grasp.h takes what comes within reach of
    // closed jaws): the shipped expert runs rely on it near the incision (an open defect:
    // docs/architecture.md "Open").
    models::GraspState& held = catheter_grasps_[t];
    if (duct_grasps_[t].grasping() && !held.grasping()) {
      held.last_opening_rad = tools[t].jaws.opening_rad;
    } else {
      const models::GraspOutput g =
          models::update_grasp(settings.catheter_grasp, tools[t].jaws, model_->catheter_model(),
                               catheter_.get(), &held, dt);
      squeeze_[t] = g.squeeze_n;
    }
    if (duct_state_) {
      const models::DuctGraspOutput d =
          models::update_duct_grasp(settings.duct_grasp, tools[t].jaws, duct.pose_WD, duct.rest_D,
                                    *duct.model, duct_state_.get(), &duct_grasps_[t]);
      squeeze_[t] = std::max(squeeze_[t], d.squeeze_n);
      duct_grasp_force_n_[t] = d.force_on_tool_W.norm();
      duct_squeeze_n_[t] = d.squeeze_n;
    }
  }
}

void TissueWorld::find_catheter_contacts() noexcept {
  // 2. The catheter's contacts: organs at rest, the duct as it is now.
  models::clear_contacts(catheter_.get());
  catheter_contacts_ = 0;
  for (int32_t i = 0; i < static_cast<int32_t>(organs_.size()); ++i) {
    OrganState& s = organs_[static_cast<size_t>(i)];
    const OrganTissue& t = model_->organ(i);
    s.reaction_count = models::update_surface_contacts(
        contact_surface(i), organ_pose_W_[static_cast<size_t>(i)], s.contact, s.tracking.get(),
        catheter_.get(), s.reactions, t.open_faces);
    catheter_contacts_ += s.reaction_count;
    if (t.kind == TissueKind::kDuct) set_duct_wall_velocities(s);
  }
}

// The duct's wall moves (grasped, pushed): the catheter's friction in it acts on the slip
// relative to the wall, the mean velocity of the touched primitive's nodes over the last step.
void TissueWorld::set_duct_wall_velocities(const OrganState& s) noexcept {
  const haptics::MeshDatabase& wall = *duct_wall_;
  for (int32_t k = 0; k < s.reaction_count; ++k) {
    const models::SurfaceReaction& r = s.reactions[static_cast<size_t>(k)];
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    double count = 0.0;
    auto add = [&](int32_t v) {
      sum += duct_velocities_W_[static_cast<size_t>(v)];
      count += 1.0;
    };
    if (r.primitive.kind == haptics::PrimitiveKind::kFace) {
      for (const int32_t v : wall.face_vertices(r.primitive.index)) add(v);
    } else if (r.primitive.kind == haptics::PrimitiveKind::kEdge) {
      for (const int32_t v : wall.edge_vertices(r.primitive.index)) add(v);
    } else {
      add(r.primitive.index);
    }
    catheter_->contact_surface_velocity[static_cast<size_t>(r.particle)] = sum / count;
  }
}

bool TissueWorld::set_stiffness(int32_t organ, double stiffness_n_per_m) noexcept {
  if (organ < 0 || static_cast<size_t>(organ) >= organs_.size() ||
      !std::isfinite(stiffness_n_per_m) || stiffness_n_per_m <= 0.0) {
    return false;
  }
  organs_[static_cast<size_t>(organ)].contact.stiffness_n_per_m = stiffness_n_per_m;
  return true;
}

bool TissueWorld::dent_local_organ(int32_t organ, const std::array<ToolModelInput, 2>& tools,
                                   std::span<const models::SurfaceReaction> reactions) noexcept {
  // 4. Dents: the catheter's (conforming), then the tools' (their share of the push).
  const OrganTissue& t = model_->organ(organ);
  OrganState& s = organs_[static_cast<size_t>(organ)];
  int32_t n = models::catheter_dents(*t.local, *t.rest, Eigen::Isometry3d::Identity(),
                                     s.contact.stiffness_n_per_m, reactions, s.dents);
  // Each tool contact's penetration is its tool's displacement into the rest surface (its
  // depth below the dent the haptic loop felt, force / k, plus that dent's depth there:
  // rest_contact), so the dent takes surface_share of the tool's displacement and the tool
  // feels (1 - share) k (models/local_deformation.h). Contacts near one another (a tool's
  // three segments on one spot, or both tools) share one push: each dents by its penetration
  // over the number of contacts within R of it, so n contacts on one spot take share of
  // their (mean) displacement once. Summed in full, they would take n times share of it: from
  // n = 1 / share on (2 at the default 0.5) the dent would reach or pass the tool, and the
  // proxies, whose tool did not move, lose the surface (the tool ends up inside the organ with
  // no force).
  const double reach2 = t.local->settings().radius_m * t.local->settings().radius_m;
  auto contacts_near = [&](const Eigen::Vector3d& p) {
    int32_t count = 0;
    for (const ToolModelInput& other : tools) {
      for (int32_t c = 0; c < other.contact_count && other.valid; ++c) {
        const ToolContact& oc = other.contacts[static_cast<size_t>(c)];
        if (oc.organ == organ && (oc.point_W - p).squaredNorm() < reach2) ++count;
      }
    }
    return std::max(count, 1);
  };
  for (const ToolModelInput& tool : tools) {
    for (int32_t c = 0; c < tool.contact_count && tool.valid; ++c) {
      const ToolContact& tc = tool.contacts[static_cast<size_t>(c)];
      if (tc.organ != organ || n >= static_cast<int32_t>(s.dents.size())) continue;
      models::DeformationContact dent = models::rest_contact(
          *t.local, *t.rest, s.local->positions, tc.primitive, tc.point_W, tc.force_on_organ_W,
          tc.stiffness_n_per_m > 0.0 ? tc.stiffness_n_per_m : s.contact.stiffness_n_per_m);
      dent.penetration_O /= static_cast<double>(contacts_near(tc.point_W));
      // A contact that finds no face on the rest shape is no dent (as catheter_dents skips
      // it): deform() would refuse it, and that is not a model fault.
      if (dent.face >= 0) s.dents[static_cast<size_t>(n++)] = dent;
    }
  }
  if (injected_ == ModelFaultKind::kLocalDeformation && n < static_cast<int32_t>(s.dents.size())) {
    models::DeformationContact& bad = s.dents[static_cast<size_t>(n++)];
    bad = models::DeformationContact{};
    bad.face = 0;
    bad.penetration_O.x() = std::numeric_limits<double>::quiet_NaN();
    injected_ = ModelFaultKind::kNone;  // the first locally deformed organ only
  }
  // The tools' segments without a contact on this organ: its surface does not pass them.
  std::array<models::DeformationObstacle, 6> obstacles;
  size_t obstacle_count = 0;
  for (const ToolModelInput& tool : tools) {
    if (!tool.valid || !tool.has_proxies) continue;
    for (int32_t seg = 0; seg < 3; ++seg) {
      bool touching = false;
      for (int32_t c = 0; c < tool.contact_count; ++c) {
        const ToolContact& tc = tool.contacts[static_cast<size_t>(c)];
        touching = touching || (tc.organ == organ && tc.segment == seg);
      }
      const Eigen::Vector3d& a = tool.proxy_a_W[static_cast<size_t>(seg)];
      const Eigen::Vector3d& b = tool.proxy_b_W[static_cast<size_t>(seg)];
      // A segment of no length is none (the session writes zeros for a proxy not finite).
      if (touching || a == b) continue;
      obstacles[obstacle_count++] = {a, b};
    }
  }
  const bool ok = models::deform(*t.local, {s.dents.data(), static_cast<size_t>(n)}, s.local.get(),
                                 {obstacles.data(), obstacle_count});
  deepest_dent_ = std::max(deepest_dent_, s.local->deepest_m);
  return ok;
}

bool TissueWorld::step_duct(int32_t organ, const std::array<ToolModelInput, 2>& tools,
                            std::span<const models::SurfaceReaction> reactions,
                            double dt) noexcept {
  // 5. The duct: reactions into its modes (duct frame), then its step.
  const DuctTissue& duct = model_->duct();
  const Eigen::Matrix3d r_DW = duct.pose_WD.linear().transpose();
  for (const models::SurfaceReaction& r : reactions) {
    models::apply_surface_force(*duct_wall_, r.primitive, r.point_O, r_DW * r.force_on_surface_W,
                                duct_state_.get());
  }
  for (const ToolModelInput& tool : tools) {
    for (int32_t c = 0; c < tool.contact_count && tool.valid; ++c) {
      const ToolContact& tc = tool.contacts[static_cast<size_t>(c)];
      if (tc.organ != organ) continue;
      models::apply_surface_force(*duct_wall_, tc.primitive, tc.point_W, r_DW * tc.force_on_organ_W,
                                  duct_state_.get());
    }
  }
  if (injected_ == ModelFaultKind::kModalShell) {
    const Eigen::Vector3d nan = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
    models::apply_surface_force(*duct_wall_, {haptics::PrimitiveKind::kFace, 0},
                                duct_positions_W_[0], nan, duct_state_.get());
  }
  const bool ok = models::step_modal_shell(*duct.model, duct_state_.get(), dt);
  // The wall the catheter meets is refitted only when it moved: a duct at rest (most of a
  // session) costs nothing here.
  double moved = 0.0;
  for (size_t v = 0; v < duct_positions_W_.size(); ++v) {
    const Eigen::Vector3d p = duct.pose_WD * (duct.rest_D[v] + duct_state_->displacement[v]);
    moved = std::max(moved, (p - duct_positions_W_[v]).squaredNorm());
    duct_velocities_W_[v] = (p - duct_positions_W_[v]) / dt;
    duct_positions_W_[v] = p;
    deepest_dent_ = std::max(deepest_dent_, duct_state_->displacement[v].norm());
  }
  if (moved > 0.0) {
    duct_wall_->set_positions(duct_positions_W_, duct_all_nodes_, duct_scratch_.get());
  }
  return ok;
}

void TissueWorld::catheter_wrench(int32_t organ, const Eigen::Vector3d& com_W,
                                  Eigen::Vector3d* force_W,
                                  Eigen::Vector3d* torque_W) const noexcept {
  force_W->setZero();
  torque_W->setZero();
  if (organ < 0 || static_cast<size_t>(organ) >= organs_.size()) return;
  const OrganState& s = organs_[static_cast<size_t>(organ)];
  const Eigen::Isometry3d& pose = organ_pose_W_[static_cast<size_t>(organ)];
  for (int32_t k = 0; k < s.reaction_count; ++k) {
    const models::SurfaceReaction& r = s.reactions[static_cast<size_t>(k)];
    *force_W += r.force_on_surface_W;
    *torque_W += (pose * r.point_O - com_W).cross(r.force_on_surface_W);
  }
}

std::vector<SurfaceDeformation> TissueWorld::make_deformations() const {
  std::vector<SurfaceDeformation> d;
  d.reserve(organs_.size());
  for (int32_t i = 0; i < model_->organ_count(); ++i) {
    const OrganTissue& t = model_->organ(i);
    d.emplace_back(t.kind == TissueKind::kFixed ? 0 : t.surface.positions.size());
  }
  return d;
}

void TissueWorld::write_deformations(std::vector<SurfaceDeformation>* out) const noexcept {
  for (size_t i = 0; i < organs_.size() && i < out->size(); ++i) {
    const TissueKind kind = model_->organ(static_cast<int32_t>(i)).kind;
    const OrganState& s = organs_[i];
    SurfaceDeformation& d = (*out)[i];
    d.count = 0;
    const size_t cap = std::min(d.vertex.size(), d.position.size());
    if (kind == TissueKind::kLocal) {
      for (const int32_t v : s.local->displaced) {
        if (static_cast<size_t>(d.count) >= cap) break;
        d.vertex[static_cast<size_t>(d.count)] = v;
        d.position[static_cast<size_t>(d.count++)] = s.local->positions[static_cast<size_t>(v)];
      }
    } else if (kind == TissueKind::kDuct) {
      for (size_t v = 0; v < duct_positions_W_.size() && v < cap; ++v) {
        if (duct_state_->displacement[v].squaredNorm() == 0.0) continue;
        d.vertex[static_cast<size_t>(d.count)] = static_cast<int32_t>(v);
        d.position[static_cast<size_t>(d.count++)] = duct_positions_W_[v];
      }
    }
  }
}

}  // namespace lap::sim

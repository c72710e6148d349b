#include "sim/tissue_world.h"

#include <algorithm>
#include <stdexcept>

#include "sim/duct_fit.h"
#include "sim/modal_shell_cache.h"

namespace lap::sim {

std::unique_ptr<TissueWorld> TissueWorld::build(const Scene& scene,
                                                const TissueWorldSettings& settings,
                                                std::vector<std::string>* notes) {
  std::unique_ptr<TissueWorld> w(new TissueWorld());
  w->settings_ = settings;
  try {
    w->catheter_model_ =
        std::make_unique<models::CatheterModel>(models::CatheterModel::build(settings.catheter));
  } catch (const std::exception& e) {
    throw std::runtime_error(std::string("catheter: ") + e.what());
  }
  w->catheter_ = std::make_unique<models::CatheterState>(
      *w->catheter_model_, settings.catheter_start_W, settings.catheter_direction_W);
  w->catheter_->fixed[0] = 1;  // where it enters: held
  const size_t particles = w->catheter_->positions.size();

  for (size_t i = 0; i < scene.organs.size(); ++i) {
    const Organ& organ = scene.organs[i];
    OrganModel m;
    m.stiffness_n_per_m = organ.material.stiffness_n_per_m;
    m.contact.clearance_m = w->catheter_model_->radius_m();
    m.contact.stiffness_n_per_m = organ.material.stiffness_n_per_m;
    m.contact.damping_n_s_per_m = organ.material.damping_n_s_per_m;
    try {
      if (organ.model == models::ModelKind::kModalShell) {
        if (w->duct_organ_ >= 0)
          throw std::runtime_error("only one modal-shell organ is supported");
        const DuctFit fit = fit_duct(organ.mesh, settings.duct_wall_thickness_m);
        const models::DuctShell shell = models::make_duct_shell(fit.duct);
        const std::filesystem::path dir =
            settings.mode_cache_dir.empty() ? default_mode_cache_dir() : settings.mode_cache_dir;
        ModalShellLoad load = load_or_build_modal_shell(
            shell.mesh, shell.held_dof, models::default_duct_modal_settings(fit.duct), dir);
        if (!load.note.empty() && notes != nullptr) notes->push_back(organ.name + ": " + load.note);
        w->duct_model_ = std::make_unique<models::ModalShellModel>(std::move(load.model));
        w->duct_state_ = std::make_unique<models::ModalShellState>(*w->duct_model_);
        w->duct_pose_WD_ = fit.pose_WD;
        w->duct_rest_D_ = shell.mesh.nodes;
        m.kind = Kind::kDuct;
        m.surface = models::triangulate(shell.mesh);
        m.surface.transform(Eigen::Affine3d(fit.pose_WD.matrix()));
        w->duct_wall_ =
            std::make_unique<haptics::MeshDatabase>(haptics::MeshDatabase::build(m.surface));
        w->duct_scratch_ = std::make_unique<haptics::MeshUpdateScratch>(*w->duct_wall_);
        w->duct_positions_W_ = m.surface.positions;
        w->duct_all_nodes_.resize(m.surface.positions.size());
        for (size_t v = 0; v < w->duct_all_nodes_.size(); ++v) {
          w->duct_all_nodes_[v] = static_cast<int32_t>(v);
        }
        m.contact.clearance_m += 0.5 * settings.duct_wall_thickness_m;  // its mid-surface
        m.contact.keep_side = true;  // the catheter may be inside or outside
        w->duct_organ_ = static_cast<int32_t>(i);
      } else {
        m.surface = organ.mesh;
        m.rest = std::make_unique<haptics::MeshDatabase>(haptics::MeshDatabase::build(m.surface));
        if (organ.model == models::ModelKind::kLocal) {
          m.kind = Kind::kLocal;
          m.local = std::make_unique<models::LocalDeformationModel>(
              models::LocalDeformationModel::build(*m.rest, settings.local));
          m.local_state = std::make_unique<models::LocalDeformationState>(*m.local);
          m.dents.resize(particles + static_cast<size_t>(2 * ToolModelInput::kMaxContacts));
        }
      }
    } catch (const std::exception& e) {
      throw std::runtime_error(organ.name + ": " + e.what());
    }
    const haptics::MeshDatabase& contact_surface = m.kind == Kind::kDuct ? *w->duct_wall_ : *m.rest;
    m.tracking = std::make_unique<models::SurfaceTracking>(
        contact_surface, Eigen::Isometry3d::Identity(), *w->catheter_);
    m.reactions.resize(particles);
    w->organs_.push_back(std::move(m));
  }
  return w;
}

void TissueWorld::step(const std::array<ToolModelInput, 2>& tools, double dt) noexcept {
  models::CatheterState& cath = *catheter_;
  // 1. Grasps (their anchors are set afresh each step).
  if (duct_state_) models::clear_node_anchors(duct_state_.get());
  for (size_t t = 0; t < 2; ++t) {
    squeeze_[t] = 0.0;
    if (!tools[t].valid) continue;
    const models::GraspOutput g = models::update_grasp(
        settings_.catheter_grasp, tools[t].jaws, *catheter_model_, &cath, &catheter_grasps_[t]);
    squeeze_[t] = g.squeeze_n;
    if (duct_state_) {
      const models::DuctGraspOutput d = models::update_duct_grasp(
          settings_.duct_grasp, tools[t].jaws, duct_pose_WD_, duct_rest_D_, *duct_model_,
          duct_state_.get(), &duct_grasps_[t]);
      squeeze_[t] = std::max(squeeze_[t], d.squeeze_n);
    }
  }
  // 2. The catheter's contacts: organs at rest, the duct as it is now.
  models::clear_contacts(&cath);
  catheter_contacts_ = 0;
  for (OrganModel& m : organs_) {
    const haptics::MeshDatabase& s = m.kind == Kind::kDuct ? *duct_wall_ : *m.rest;
    m.reaction_count = models::update_surface_contacts(s, Eigen::Isometry3d::Identity(), m.contact,
                                                       m.tracking.get(), &cath, m.reactions);
    catheter_contacts_ += m.reaction_count;
  }
  // 3. The catheter.
  (void)models::step_catheter(*catheter_model_, &cath, dt);
  deepest_dent_ = 0.0;
  for (size_t i = 0; i < organs_.size(); ++i) {
    OrganModel& m = organs_[i];
    const std::span<models::SurfaceReaction> reactions(m.reactions.data(),
                                                       static_cast<size_t>(m.reaction_count));
    models::settle_reactions(cath, reactions);
    if (m.kind == Kind::kLocal) {
      // 4. Dents: the catheter's (conforming), then the tools' (their share of the push).
      int32_t n = models::catheter_dents(*m.local, *m.rest, Eigen::Isometry3d::Identity(),
                                         m.stiffness_n_per_m, reactions, m.dents);
      // Each tool contact's force comes from how deep its segment lies below the dent the last
      // step left, so the dents and the forces alternate between the loops. Contacts near one
      // another (a tool's three segments on one spot, or both tools) share one push: each
      // dents by its force over the number of contacts within R of it. Summed in full, n
      // contacts on one spot would dent n times share of the penetration: from n = 2 on the
      // dent overshoots the tool and swings back through it, and the proxies, whose tool did
      // not move, lose the surface (the tool ends up inside the organ with no force).
      const double reach2 = m.local->settings().radius_m * m.local->settings().radius_m;
      auto contacts_near = [&](const Eigen::Vector3d& p) {
        int32_t count = 0;
        for (const ToolModelInput& other : tools) {
          for (int32_t c = 0; c < other.contact_count && other.valid; ++c) {
            const ToolContact& oc = other.contacts[static_cast<size_t>(c)];
            if (oc.organ == static_cast<int32_t>(i) && (oc.point_W - p).squaredNorm() < reach2) {
              ++count;
            }
          }
        }
        return std::max(count, 1);
      };
      for (const ToolModelInput& tool : tools) {
        for (int32_t c = 0; c < tool.contact_count && tool.valid; ++c) {
          const ToolContact& tc = tool.contacts[static_cast<size_t>(c)];
          if (tc.organ != static_cast<int32_t>(i) || n >= static_cast<int32_t>(m.dents.size())) {
            continue;
          }
          const Eigen::Vector3d share_of_push =
              tc.force_on_organ_W / static_cast<double>(contacts_near(tc.point_W));
          m.dents[static_cast<size_t>(n++)] =
              models::rest_contact(*m.local, *m.rest, m.local_state->positions, tc.primitive,
                                   tc.point_W, share_of_push, m.stiffness_n_per_m);
        }
      }
      (void)models::deform(*m.local, {m.dents.data(), static_cast<size_t>(n)}, m.local_state.get());
      for (const int32_t v : m.local_state->displaced) {
        deepest_dent_ = std::max(
            deepest_dent_,
            (m.local_state->positions[static_cast<size_t>(v)] - m.local->rest_position(v)).norm());
      }
    } else if (m.kind == Kind::kDuct) {
      // 5. The duct: reactions into its modes (duct frame), then its step.
      const Eigen::Matrix3d r_DW = duct_pose_WD_.linear().transpose();
      for (const models::SurfaceReaction& r : reactions) {
        models::apply_surface_force(*duct_wall_, r.primitive, r.point_O,
                                    r_DW * r.force_on_surface_W, duct_state_.get());
      }
      for (const ToolModelInput& tool : tools) {
        for (int32_t c = 0; c < tool.contact_count && tool.valid; ++c) {
          const ToolContact& tc = tool.contacts[static_cast<size_t>(c)];
          if (tc.organ != static_cast<int32_t>(i)) continue;
          models::apply_surface_force(*duct_wall_, tc.primitive, tc.point_W,
                                      r_DW * tc.force_on_organ_W, duct_state_.get());
        }
      }
      (void)models::step_modal_shell(*duct_model_, duct_state_.get(), dt);
      // The wall the catheter meets is refitted only when it moved: a duct at rest (most of a
      // session) costs nothing here.
      double moved = 0.0;
      for (size_t v = 0; v < duct_positions_W_.size(); ++v) {
        const Eigen::Vector3d p = duct_pose_WD_ * (duct_rest_D_[v] + duct_state_->displacement[v]);
        moved = std::max(moved, (p - duct_positions_W_[v]).squaredNorm());
        duct_positions_W_[v] = p;
        deepest_dent_ = std::max(deepest_dent_, duct_state_->displacement[v].norm());
      }
      if (moved > 0.0) {
        duct_wall_->set_positions(duct_positions_W_, duct_all_nodes_, duct_scratch_.get());
      }
    }
  }
}

std::vector<SurfaceDeformation> TissueWorld::make_deformations() const {
  std::vector<SurfaceDeformation> d;
  d.reserve(organs_.size());
  for (const OrganModel& m : organs_) {
    d.emplace_back(m.kind == Kind::kFixed ? 0 : m.surface.positions.size());
  }
  return d;
}

void TissueWorld::write_deformations(std::vector<SurfaceDeformation>* out) const noexcept {
  for (size_t i = 0; i < organs_.size() && i < out->size(); ++i) {
    const OrganModel& m = organs_[i];
    SurfaceDeformation& d = (*out)[i];
    d.count = 0;
    const size_t cap = std::min(d.vertex.size(), d.position.size());
    if (m.kind == Kind::kLocal) {
      for (const int32_t v : m.local_state->displaced) {
        if (static_cast<size_t>(d.count) >= cap) break;
        d.vertex[static_cast<size_t>(d.count)] = v;
        d.position[static_cast<size_t>(d.count++)] =
            m.local_state->positions[static_cast<size_t>(v)];
      }
    } else if (m.kind == Kind::kDuct) {
      for (size_t v = 0; v < duct_positions_W_.size() && v < cap; ++v) {
        if (duct_state_->displacement[v].squaredNorm() == 0.0) continue;
        d.vertex[static_cast<size_t>(d.count)] = static_cast<int32_t>(v);
        d.position[static_cast<size_t>(d.count++)] = duct_positions_W_[v];
      }
    }
  }
}

}  // namespace lap::sim

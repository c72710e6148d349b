#pragma once
/// \file
/// The catheter as a mass-spring-damper chain (thesis §7.7(3), eq. 7-1): particles along the
/// centre line, linear springs between neighbours, torsional (bending) springs at each interior
/// particle, damping. Contacts act on the particles through point proxies with the catheter's
/// radius (sim/).
///
/// Energies: stretch ½ k_l (l − l0)² per segment; bending k_b (1 − cos θ) = ½ k_b |t1 − t2|² per
/// interior particle (t1, t2 the unit tangents either side; ≈ ½ k_b θ², so the moment is k_b θ
/// as in eq. 7-1 for small angles and the chain is a discrete Euler–Bernoulli rod with
/// EI = k_b l0); drag −b v per particle (eq. 7-1) and damping along each segment.
///
/// Integration: linearly implicit backward Euler (Baraff & Witkin 1998),
///     (M + dt D + dt² K) Δv = dt (f − dt K v),  v += Δv,  x += dt v,
/// with K the stretch Hessian (its transverse part clamped at zero) and the Gauss–Newton
/// Hessian of the bending residual t1 − t2 — both positive semi-definite, so the system matrix
/// is SPD. Why: a catheter is stiff in stretch (≤ 1 % strain at 1 N needs k_l ≈ 4·10⁴ N/m on
/// 5 mm segments) and light (≈ 2·10⁻⁵ kg per particle), so explicit Euler (eq. 7-2) would need
/// dt < 10⁻⁴ s; backward Euler is stable at the modelling loop's 5 ms and its numerical damping
/// only removes energy. The system is block-banded (each particle meets two neighbours each
/// side), solved by a banded Cholesky in pre-sized arrays: O(n), no allocation.
///
/// Model (immutable) apart from state (per instance), as in MuJoCo's mjModel and mjData.

#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <vector>

namespace lap::models {

struct CatheterSettings {
  int32_t particles = 64;
  double length_m = 0.30;
  double outer_diameter_m = 0.0025;  ///< 2–3 mm (§7.4)
  /// Project estimates for a polyurethane cholangiography catheter (not measured): E ≈ 30 MPa on
  /// a 2.5/1.5 mm tube gives EI ≈ 5·10⁻⁵ N m²; 1.2 g/cm³.
  double bending_stiffness_n_m2 = 5e-5;  ///< EI
  double linear_density_kg_per_m = 3.8e-3;
  /// Per segment; default so that 1 N stretches the catheter by 0.5 % (length nearly kept).
  double stretch_stiffness_n_per_m = 0.0;  ///< 0: 200 N / l0
  double drag_n_s_per_m = 2e-4;            ///< b of eq. 7-1, per particle
  double stretch_damping_n_s_per_m = 0.5;  ///< along each segment
  Eigen::Vector3d gravity_m_per_s2 = Eigen::Vector3d::Zero();
  /// Coulomb friction at the contact planes is regularised (§7.6.3; a damper μN / max(|v_t|,
  /// v_stick) along the plane, inside the implicit solve): sliding faster than v_stick it is
  /// μN against the slip, slower it is viscous, so a particle loaded along the plane by F < μN
  /// creeps at F v_stick / (μN) < v_stick instead of sticking exactly. 0.5 mm/s: a choice (a
  /// held catheter creeps less than 5 mm in 10 s however it is loaded, and sticking needs no
  /// second solve per contact).
  double contact_stick_speed_m_per_s = 5e-4;
};

class CatheterModel {
 public:
  /// Throws std::invalid_argument naming the bad setting.
  static CatheterModel build(const CatheterSettings& settings);

  [[nodiscard]] const CatheterSettings& settings() const { return settings_; }
  [[nodiscard]] int32_t particle_count() const { return settings_.particles; }
  [[nodiscard]] double rest_length_m() const { return l0_; }  ///< l0, per segment
  /// Mass of particle i [kg] (the end particles carry half a segment).
  [[nodiscard]] double mass_of(int32_t i) const;
  [[nodiscard]] double stretch_stiffness() const { return k_l_; }  ///< k_l [N/m]
  [[nodiscard]] double bending_stiffness() const { return k_b_; }  ///< k_b = EI / l0 [N m]
  [[nodiscard]] double radius_m() const { return 0.5 * settings_.outer_diameter_m; }

 private:
  CatheterSettings settings_;
  double l0_ = 0.0;
  double mass_ = 0.0;
  double k_l_ = 0.0;
  double k_b_ = 0.0;
};

/// A spring (and damper) from a point of the catheter's centre line to a target: segment
/// `segment` (particles segment and segment + 1), a fraction `t` of the way along it. A grasp
/// holds the catheter by two of these at the ends of the section between its jaws (§7.6.3), so
/// it holds wherever the catheter lies, between particles too, and transmits a moment. Inside
/// the implicit solve: stable however stiff (as an explicit force it would need dt < 2 sqrt(m /
/// k) ≈ 0.3 ms).
struct CenterlineAnchor {
  int32_t segment = 0;
  double t = 0.0;  ///< in [0, 1]
  Eigen::Vector3d target_W = Eigen::Vector3d::Zero();
  /// The target's own velocity: the damper acts on the point's velocity relative to it,
  /// c (target_velocity − v) (a grasp's jaws moving; zero for a fixed target).
  Eigen::Vector3d target_velocity_W = Eigen::Vector3d::Zero();
  double stiffness_n_per_m = 0.0;
  double damping_n_s_per_m = 0.0;
};

/// A spring (and damper) between two points of the centre line, a (segment_a, t_a) and
/// b (segment_b, t_b), holding b − a at `rest_W`: E = ½ k |x_b − x_a − rest|², the damper
/// c (rest_velocity − (v_b − v_a)). It carries no net force, only a moment: a grasp holds its
/// section's shape and orientation by a chain of these while its anchors, which carry the
/// section's translation, stay as soft as the virtual coupling to the hand
/// (models/catheter_grasp.h). Its points must lie within three consecutive particles (the
/// system's band); add_link() refuses others.
struct CenterlineLink {
  int32_t segment_a = 0;
  double t_a = 0.0;
  int32_t segment_b = 0;
  double t_b = 0.0;
  Eigen::Vector3d rest_W = Eigen::Vector3d::Zero();
  Eigen::Vector3d rest_velocity_W = Eigen::Vector3d::Zero();
  double stiffness_n_per_m = 0.0;
  double damping_n_s_per_m = 0.0;
};

/// Coulomb friction on a group of anchors (a grasp's held section, §7.6.3): along `axis_W` the
/// anchors bear at most `limit_n` together. Each step solves them sticking; if their axial force
/// at the end of the step exceeds the limit, the step is solved again with the group slipping:
/// held across the axis only, and `limit_n` against the sticking force's direction (exact
/// Coulomb for the step, with no overshoot: the catheter slides only where sticking would have
/// needed more than the limit).
struct AnchorFriction {
  Eigen::Vector3d axis_W = Eigen::Vector3d::UnitZ();
  double limit_n = 0.0;
  int32_t first_anchor = 0;
  int32_t anchor_count = 0;
};
/// What a friction group did in the last step.
struct AnchorFrictionResult {
  bool slipped = false;
  double axial_force_n = 0.0;  ///< on the catheter along the axis (sticking: what it bore)
};

struct CatheterState {
  std::vector<Eigen::Vector3d> positions;       ///< n x 3 [m]
  std::vector<Eigen::Vector3d> velocities;      ///< n x 3 [m/s]
  std::vector<Eigen::Vector3d> external_force;  ///< n x 3 [N], cleared by each step
  std::vector<uint8_t> fixed;                   ///< n: 1 = held in place (clamp)
  /// Anchors on the centre line (grasps); the first anchor_count count.
  static constexpr int32_t kMaxAnchors = 16;  ///< two grasps of up to 6 anchors, and spare
  std::array<CenterlineAnchor, kMaxAnchors> anchors{};
  int32_t anchor_count = 0;
  /// Links between centre-line points (grasps' held sections); the first link_count count.
  static constexpr int32_t kMaxLinks = 14;  ///< two grasps of up to 7 held points each
  std::array<CenterlineLink, kMaxLinks> links{};
  int32_t link_count = 0;
  static constexpr int32_t kMaxFrictions = 3;  ///< a grasp per tool, the incision's rim
  std::array<AnchorFriction, kMaxFrictions> frictions{};
  int32_t friction_count = 0;
  /// Per friction slot, what it did in the last step (kept until a step overwrites it).
  std::array<AnchorFrictionResult, kMaxFrictions> friction_results{};
  std::array<bool, kMaxFrictions> slipping{};  ///< step workspace
  /// Contact planes (§7.6.3): particle i is pushed out along `contact_normal` while
  /// n · x < contact_offset, by a spring (and damper) along n only, inside the implicit solve.
  /// Set each modelling step by the contact search (catheter_contacts.h); stiffness 0: none.
  /// Friction acts along the plane (CatheterSettings::contact_stick_speed_m_per_s).
  std::vector<Eigen::Vector3d> contact_normal;  ///< n, unit
  std::vector<double> contact_offset;           ///< n [m]
  std::vector<double> contact_stiffness;        ///< n [N/m]
  std::vector<double> contact_damping;          ///< n [N s/m]
  /// Coulomb friction along each contact plane: μ (0: none), and the velocity of the surface
  /// there [m/s] (the friction acts on the slip, the particle's velocity relative to it).
  std::vector<double> contact_friction;
  std::vector<Eigen::Vector3d> contact_surface_velocity;
  /// Step workspace: the friction's damper c_t [N s/m] per particle as the last solve used it
  /// (settle_reactions reads it for the reaction on the surface).
  std::vector<double> contact_friction_damping;
  // Workspace of the step (sized once): the band of the system matrix, its right-hand side.
  std::vector<double> band;  ///< (3n) x (w + 1), lower band, w = 8
  std::vector<double> rhs;   ///< 3n
  /// Energy guard: a step that gains energy without input is redone as two half steps, at most
  /// kGuardDepth − 1 times nested (saved states per level).
  static constexpr int kGuardDepth = 5;
  std::vector<Eigen::Vector3d> saved_positions;   ///< kGuardDepth x n
  std::vector<Eigen::Vector3d> saved_velocities;  ///< kGuardDepth x n
  int64_t guard_refinements = 0;                  ///< steps split by the guard, in total

  /// Straight along `direction` from `start`, at rest (setup; allocates).
  CatheterState(const CatheterModel& model, const Eigen::Vector3d& start,
                const Eigen::Vector3d& direction);
};

/// The centre line's point on segment `segment` at fraction t (clamped to the catheter).
[[nodiscard]] Eigen::Vector3d centerline_point(const CatheterModel& model,
                                               const std::vector<Eigen::Vector3d>& positions,
                                               int32_t segment, double t);
/// Adds an anchor; false (nothing added) when all kMaxAnchors are in use or it is not on the
/// catheter.
bool add_anchor(const CatheterModel& model, const CenterlineAnchor& anchor,
                CatheterState* state) noexcept;
/// Adds a link; false (nothing added) when all kMaxLinks are in use, it is not on the catheter,
/// or its points span more than three consecutive particles.
bool add_link(const CatheterModel& model, const CenterlineLink& link,
              CatheterState* state) noexcept;
/// Adds friction to the anchors from `first_anchor` to the last one added; its slot, or -1 when
/// all are in use.
int32_t add_anchor_friction(const Eigen::Vector3d& axis_W, double limit_n, int32_t first_anchor,
                            CatheterState* state) noexcept;
/// Removes the anchors, the links and the anchors' friction (before the grasps set them for the
/// next step); the last step's friction results stay readable.
void clear_anchors(CatheterState* state) noexcept;

/// The friction force on particle i at its velocity now, as the last step applied it [N]: along
/// its contact plane, against its slip (zero without a contact or friction).
[[nodiscard]] Eigen::Vector3d contact_friction_force(const CatheterState& state, int32_t i);

/// Kinetic + stretch + bending + anchor- and link-spring + contact energy (gravity and external
/// forces excluded) [J].
[[nodiscard]] double catheter_energy(const CatheterModel& model, const CatheterState& state);
/// Potential energy in gravity [J] (relative to the origin).
[[nodiscard]] double catheter_gravity_energy(const CatheterModel& model,
                                             const CatheterState& state);

/// One step of dt (implicit, energy-guarded). External forces are applied and then cleared;
/// anchors stay until clear_anchors().
/// Returns false (velocities zeroed) when the input or result is not finite or the system
/// matrix is not positive definite.
bool step_catheter(const CatheterModel& model, CatheterState* state, double dt) noexcept;

}  // namespace lap::models

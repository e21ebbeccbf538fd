// WbcModel construction: MJCF parsing (Pinocchio, with the loop constraints), floating-base check,
// frame and joint lookup, actuation matrix, loop closures and their dependent coordinates.
// This translation unit holds the Pinocchio MJCF parser only (the slowest header to compile).
#include <pinocchio/parsers/mjcf.hpp>

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <Eigen/SVD>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "lipmpcc/wbc/dynamics.hpp"
#include "lipmpcc/wbc/model.hpp"
#include "pinocchio_model.hpp"

namespace lipmpcc::wbc {

namespace {

struct ParsedModel {
  pinocchio::Model model;
  std::vector<pinocchio::PointAnchorConstraintModel> point_anchors;  // <equality connect>
  std::vector<pinocchio::FrameAnchorConstraintModel> frame_anchors;  // <equality weld>
  std::string base_kind;
  int base_quat_idx = 3;
  pinocchio::JointIndex base_joint = 1;
};

/// Sub-joint short names of a composite joint.
std::vector<std::string> compositeParts(const pinocchio::JointModel& joint) {
  std::vector<std::string> parts;
  const auto* comp = boost::get<pinocchio::JointModelComposite>(&joint.toVariant());
  if (comp == nullptr) return parts;
  for (const auto& sub : comp->joints) parts.push_back(pinocchio::JointModel(sub).shortname());
  return parts;
}

bool isSlide(const std::string& shortname) {
  return shortname == "JointModelPX" || shortname == "JointModelPY" || shortname == "JointModelPZ" ||
         shortname == "JointModelPrismaticUnaligned";
}

/// Parses the MJCF with its loop constraints and identifies the floating base on `torso_body`.
ParsedModel parseMjcf(const std::string& path, const std::string& torso_body) {
  {
    std::ifstream probe(path);
    if (!probe.good()) throw std::invalid_argument("mjcf_path: cannot open '" + path + "'");
  }
  ParsedModel p;
  try {
    pinocchio::mjcf::buildModel(path, p.model, p.point_anchors, p.frame_anchors);
  } catch (const std::exception& e) {
    throw std::runtime_error("mjcf_path: Pinocchio could not parse '" + path + "': " + e.what());
  }
  const pinocchio::Model& m = p.model;
  if (!m.existFrame(torso_body, pinocchio::BODY))
    throw std::invalid_argument("torso body: no body named '" + torso_body + "' in the MJCF model");
  const pinocchio::JointIndex root = m.frames[m.getFrameId(torso_body, pinocchio::BODY)].parentJoint;
  if (root == 0) {
    // Fixed-base file (root body without a joint): add the floating base ourselves.
    p = ParsedModel();
    try {
      pinocchio::mjcf::buildModel(path, pinocchio::JointModelFreeFlyer(), p.model, p.point_anchors,
                                  p.frame_anchors);
    } catch (const std::exception& e) {
      throw std::runtime_error("mjcf_path: Pinocchio could not parse '" + path + "': " + e.what());
    }
    p.base_kind = "added free-flyer";
    p.base_quat_idx = 3;
    p.base_joint = 1;
    return p;
  }
  const std::string kind = m.joints[root].shortname();
  const std::vector<std::string> parts = compositeParts(m.joints[root]);
  const bool slide_ball = parts.size() == 4 && isSlide(parts[0]) && isSlide(parts[1]) &&
                          isSlide(parts[2]) && parts[3] == "JointModelSpherical" && m.nvs[root] == 6;
  if (m.parents[root] != 0 || !(kind == "JointModelFreeFlyer" || slide_ball))
    throw std::invalid_argument(
        "floating base: a free joint, or 3 slide joints followed by a ball joint, on the torso body '" +
        torso_body + "' at the root of the tree (found " +
        (m.parents[root] != 0 ? std::string("a torso that is not the root body") : kind) + ")");
  p.base_kind = slide_ball ? "slide+ball" : "free joint";
  p.base_quat_idx = m.idx_qs[root] + 3;
  p.base_joint = root;
  return p;
}

/// Rows spanning the left null space of B (n x nu): identity rows where B is zero, plus the left
/// null space of the actuated rows if actuators are coupled (rank deficient).
Mat leftNullRows(const Mat& B) {
  const Eigen::Index n = B.rows(), nu = B.cols();
  std::vector<Eigen::Index> zero_rows, act_rows;
  for (Eigen::Index i = 0; i < n; ++i)
    (nu == 0 || B.row(i).cwiseAbs().maxCoeff() == 0.0 ? zero_rows : act_rows).push_back(i);
  const auto n_act = static_cast<Eigen::Index>(act_rows.size());
  Mat B_act(n_act, nu);
  for (Eigen::Index r = 0; r < n_act; ++r) B_act.row(r) = B.row(act_rows[static_cast<std::size_t>(r)]);
  Eigen::JacobiSVD<Mat> svd(B_act, Eigen::ComputeFullU | Eigen::ComputeFullV);
  svd.setThreshold(1e-10);
  const Eigen::Index rank = svd.rank();
  const Eigen::Index n_extra_null = n_act - rank;
  Mat N_T = Mat::Zero(static_cast<Eigen::Index>(zero_rows.size()) + n_extra_null, n);
  for (std::size_t r = 0; r < zero_rows.size(); ++r) N_T(static_cast<Eigen::Index>(r), zero_rows[r]) = 1.0;
  for (Eigen::Index c = 0; c < n_extra_null; ++c) {
    const Eigen::Index row = static_cast<Eigen::Index>(zero_rows.size()) + c;
    for (Eigen::Index r = 0; r < n_act; ++r)
      N_T(row, act_rows[static_cast<std::size_t>(r)]) = svd.matrixU()(r, rank + c);
  }
  return N_T;
}

pinocchio::JointIndex findJoint(const pinocchio::Model& m, const std::string& name,
                                const std::string& what) {
  if (!m.existJointName(name))
    throw std::invalid_argument(what + ": no joint named '" + name + "' in the MJCF model");
  return m.getJointId(name);
}

void requireOneDof(const pinocchio::Model& m, pinocchio::JointIndex j, const std::string& what) {
  if (m.nvs[j] != 1 || m.nqs[j] != 1)
    throw std::invalid_argument(what + ": joint '" + m.names[j] +
                                "' must be a 1-DoF (hinge or slide) joint");
}

}  // namespace

WbcModel::~WbcModel() = default;
WbcModel::WbcModel(const WbcModel&) = default;
WbcModel& WbcModel::operator=(const WbcModel&) = default;

WbcModel::WbcModel(const WbcModelSpec& spec) : spec_(spec) {
  auto holder = std::make_shared<detail::PinocchioModel>();
  ParsedModel parsed = parseMjcf(spec.mjcf_path, spec.torso_body);
  holder->model = std::move(parsed.model);
  pinocchio::Model& m = holder->model;
  base_kind_ = parsed.base_kind;
  base_quat_idx_ = parsed.base_quat_idx;
  base_idx_v_ = m.idx_vs[parsed.base_joint];
  if (!parsed.frame_anchors.empty())
    throw std::invalid_argument("closed loops: " + std::to_string(parsed.frame_anchors.size()) +
                                " <equality weld> constraint(s); only <equality connect> loops are supported");
  nq_ = m.nq;
  nv_ = m.nv;

  // Sole frames: an existing site frame, or an operational frame added on the foot body.
  const char* foot_label[kNumFeet] = {"left", "right"};
  for (int f = 0; f < kNumFeet; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    const std::string& site = spec.sole_sites[fi];
    if (!site.empty()) {
      if (!m.existFrame(site))
        throw std::invalid_argument(std::string(foot_label[f]) + " sole site: no frame named '" +
                                    site + "' in the MJCF model");
      sole_frames_[fi] = m.getFrameId(site);
    } else {
      const std::string& body = spec.foot_bodies[fi];
      if (!m.existFrame(body, pinocchio::BODY))
        throw std::invalid_argument(std::string(foot_label[f]) + " foot body: no body named '" +
                                    body + "' in the MJCF model");
      const auto body_id = m.getFrameId(body, pinocchio::BODY);
      const pinocchio::Frame& bf = m.frames[body_id];
      pinocchio::SE3 offset(Mat3::Identity(), spec.sole_offsets[fi]);
      const std::string name = "wbc_" + std::string(foot_label[f]) + "_sole";
      sole_frames_[fi] = m.addFrame(
          pinocchio::Frame(name, bf.parentJoint, body_id, bf.placement * offset, pinocchio::OP_FRAME),
          false);
    }
  }
  torso_frame_ = m.getFrameId(spec.torso_body, pinocchio::BODY);

  if (!(spec.foot_half_length > 0.0) || !(spec.foot_half_width > 0.0))
    throw std::invalid_argument("foot half-length and half-width must be > 0");
  if (!(spec.friction > 0.0)) throw std::invalid_argument("friction must be > 0");

  // Actuation matrix.
  const auto nu = static_cast<Eigen::Index>(spec.actuated_joints.size());
  if (nu == 0) throw std::invalid_argument("actuated_joints: at least one actuator is required");
  if (spec.actuation_gains.size() != nu || spec.u_min.size() != nu || spec.u_max.size() != nu)
    throw std::invalid_argument("actuation_gains, u_min and u_max must have one entry per actuator (" +
                                std::to_string(nu) + ")");
  B_ = Mat::Zero(nv_, nu);
  for (Eigen::Index k = 0; k < nu; ++k) {
    const std::string& jn = spec.actuated_joints[static_cast<std::size_t>(k)];
    const auto j = findJoint(m, jn, "actuated_joints");
    requireOneDof(m, j, "actuated_joints");
    if (!(spec.u_min[k] < spec.u_max[k]))
      throw std::invalid_argument("actuator on joint '" + jn + "': u_min must be < u_max");
    if (spec.actuation_gains[k] == 0.0 || !std::isfinite(spec.actuation_gains[k]))
      throw std::invalid_argument("actuator on joint '" + jn + "': gain must be finite and non-zero");
    B_(m.idx_vs[j], k) += spec.actuation_gains[k];
  }
  u_min_ = spec.u_min;
  u_max_ = spec.u_max;

  N_T_ = leftNullRows(B_);
  B_pinv_ = B_.completeOrthogonalDecomposition().pseudoInverse();

  // Arm joints.
  for (const std::string& jn : spec.arm_joints) {
    const auto j = findJoint(m, jn, "arm_joints");
    requireOneDof(m, j, "arm_joints");
    arm_idx_q_.push_back(m.idx_qs[j]);
    arm_idx_v_.push_back(m.idx_vs[j]);
  }

  // Passive terms: damping from the MJCF, springs from the spec.
  if (spec.gravity.size() == 3 && spec.gravity.allFinite()) {
    m.gravity.linear(spec.gravity);
  } else if (spec.gravity.size() != 0) {
    throw std::invalid_argument("gravity: 3 finite entries [m/s^2] or none");
  }
  frictionloss_ = Vec::Zero(nv_);
  if (spec.frictionloss.size() == nv_ && spec.frictionloss.allFinite() && (spec.frictionloss.array() >= 0.0).all()) {
    frictionloss_ = spec.frictionloss;
    has_frictionloss_ = frictionloss_.maxCoeff() > 0.0;
  } else if (spec.frictionloss.size() != 0) {
    throw std::invalid_argument("frictionloss: " + std::to_string(nv_) + " finite entries >= 0 or none");
  }
  if (spec.damping.size() == 0) {
    damping_ = m.damping;
  } else if (spec.damping.size() == nv_ && spec.damping.allFinite() && (spec.damping.array() >= 0.0).all()) {
    damping_ = spec.damping;
  } else {
    throw std::invalid_argument("damping: " + std::to_string(nv_) + " finite entries >= 0 (one per velocity "
                                "coordinate) or none");
  }
  const auto n_spring = static_cast<Eigen::Index>(spec.spring_joints.size());
  if (spec.spring_stiffness.size() != n_spring || spec.spring_reference.size() != n_spring)
    throw std::invalid_argument("spring_stiffness and spring_reference must have one entry per spring joint");
  for (const std::string& jn : spec.spring_joints) {
    const auto j = findJoint(m, jn, "spring_joints");
    requireOneDof(m, j, "spring_joints");
    spring_idx_q_.push_back(m.idx_qs[j]);
    spring_idx_v_.push_back(m.idx_vs[j]);
  }

  // Bookkeeping for Python.
  for (pinocchio::JointIndex j = 1; j < static_cast<pinocchio::JointIndex>(m.njoints); ++j) {
    joint_names_.push_back(m.names[j]);
    joint_idx_q_.push_back(m.idx_qs[j]);
    joint_idx_v_.push_back(m.idx_vs[j]);
    joint_nq_.push_back(m.nqs[j]);
  }
  q_lower_ = m.lowerPositionLimit;
  q_upper_ = m.upperPositionLimit;
  // Range-limited actuated joints (Pinocchio reads MuJoCo's range; unlimited joints get +-max).
  std::vector<double> lo, hi;
  for (const std::string& jn : spec.actuated_joints) {
    const auto j = findJoint(m, jn, "actuated_joints");
    const int iq = m.idx_qs[j];
    const double a = q_lower_[iq], b = q_upper_[iq];
    if (!(std::isfinite(a) && std::isfinite(b) && std::abs(a) < 1e10 && std::abs(b) < 1e10 && a < b)) continue;
    if (std::find(limit_idx_q_.begin(), limit_idx_q_.end(), iq) != limit_idx_q_.end()) continue;
    limit_idx_q_.push_back(iq);
    limit_idx_v_.push_back(m.idx_vs[j]);
    lo.push_back(a);
    hi.push_back(b);
  }
  limit_lower_ = Eigen::Map<const Vec>(lo.data(), static_cast<Eigen::Index>(lo.size()));
  limit_upper_ = Eigen::Map<const Vec>(hi.data(), static_cast<Eigen::Index>(hi.size()));
  q_neutral_ = Vec::Zero(nq_);
  for (std::size_t i = 0; i < joint_idx_q_.size(); ++i)
    if (joint_nq_[i] == 4) q_neutral_[joint_idx_q_[i] + 3] = 1.0;  // spherical joints
  q_neutral_[base_quat_idx_ + 3] = 1.0;  // base quaternion (x, y, z, w)
  mass_ = 0.0;
  for (const auto& inertia : m.inertias) mass_ += inertia.mass();

  // Loop closures: an operational frame at each anchor.
  for (std::size_t k = 0; k < parsed.point_anchors.size(); ++k) {
    const auto& c = parsed.point_anchors[k];
    LoopClosure loop;
    loop.joint1 = m.names[c.joint1_id];
    loop.joint2 = m.names[c.joint2_id];
    loop.anchor1 = c.joint1_placement.translation();
    loop.anchor2 = c.joint2_placement.translation();
    const std::string base = "wbc_loop" + std::to_string(k);
    loop.frame1 = m.addFrame(pinocchio::Frame(base + "_anchor1", c.joint1_id, pinocchio::SE3(Mat3::Identity(), loop.anchor1),
                                              pinocchio::OP_FRAME), false);
    loop.frame2 = m.addFrame(pinocchio::Frame(base + "_anchor2", c.joint2_id, pinocchio::SE3(Mat3::Identity(), loop.anchor2),
                                              pinocchio::OP_FRAME), false);
    loops_.push_back(loop);
  }
  pin_ = std::move(holder);

  // Rigid passive springs (no motor on the joint) become holonomic rows.
  if (spec.spring_model == SpringModel::kRigid)
    for (std::size_t k = 0; k < spring_idx_v_.size(); ++k)
      if (B_.row(spring_idx_v_[k]).cwiseAbs().maxCoeff() == 0.0) rigid_springs_.push_back(static_cast<int>(k));

  qp_coords_ = QpCoordinates{nv_, B_, B_pinv_, N_T_, arm_idx_v_, limit_idx_v_, SparseRows::from(B_pinv_),
                             SparseRows::from(N_T_)};
  if (nConstraintRows() > 0 && spec.loop_formulation == LoopFormulation::kEliminate) chooseLoopCoordinates();
}

void WbcModel::chooseLoopCoordinates() {
  Vec q_ref = spec_.loop_reference_configuration;
  if (q_ref.size() == 0) q_ref = q_neutral_;
  if (q_ref.size() != nq_ || !q_ref.allFinite())
    throw std::invalid_argument("loop_reference_configuration: " + std::to_string(nq_) +
                                " finite entries (a Pinocchio configuration) or none");
  q_ref.segment<4>(base_quat_idx_).normalize();
  Mat J;
  Vec residual;
  DynamicsEvaluator(*this).loopKinematics(q_ref, J, residual);
  const Eigen::Index nr = J.rows();

  // Candidates: unactuated coordinates outside the base (the loops' passive joints and rods).
  std::vector<int> candidates;
  for (int i = 0; i < nv_; ++i) {
    const bool base = i >= base_idx_v_ && i < base_idx_v_ + 6;
    if (!base && B_.row(i).cwiseAbs().maxCoeff() == 0.0) candidates.push_back(i);
  }
  Mat Jc(nr, static_cast<Eigen::Index>(candidates.size()));
  for (std::size_t c = 0; c < candidates.size(); ++c) Jc.col(static_cast<Eigen::Index>(c)) = J.col(candidates[c]);
  Eigen::ColPivHouseholderQR<Mat> qr(Jc);
  qr.setThreshold(1e-8);
  if (qr.rank() < nr)
    throw std::invalid_argument(
        "closed loops: the " + std::to_string(loops_.size()) + " loop constraints and " +
        std::to_string(rigid_springs_.size()) + " rigid springs (" + std::to_string(nr) +
        " rows) must be independent and solvable for unactuated joints (rank " + std::to_string(qr.rank()) +
        " at the loop reference configuration)");
  std::vector<bool> is_dep(static_cast<std::size_t>(nv_), false);
  for (Eigen::Index k = 0; k < nr; ++k)
    is_dep[static_cast<std::size_t>(candidates[static_cast<std::size_t>(qr.colsPermutation().indices()[k])])] = true;
  for (int i = 0; i < nv_; ++i) (is_dep[static_cast<std::size_t>(i)] ? dependent_idx_v_ : independent_idx_v_).push_back(i);

  // The QP's coordinates: qdd[independent] = a. Dependent coordinates are unactuated, so the
  // reduced actuation Z^T B is B's independent rows.
  QpCoordinates qc;
  qc.n = static_cast<int>(independent_idx_v_.size());
  qc.B = B_(independent_idx_v_, Eigen::all);
  qc.B_pinv = qc.B.completeOrthogonalDecomposition().pseudoInverse();
  qc.N_T = leftNullRows(qc.B);
  qc.B_pinv_rows = SparseRows::from(qc.B_pinv);
  qc.N_T_rows = SparseRows::from(qc.N_T);
  std::vector<int> position(static_cast<std::size_t>(nv_), -1);
  for (std::size_t k = 0; k < independent_idx_v_.size(); ++k)
    position[static_cast<std::size_t>(independent_idx_v_[k])] = static_cast<int>(k);
  for (int i : arm_idx_v_) qc.arm_idx.push_back(position[static_cast<std::size_t>(i)]);
  for (int i : limit_idx_v_) qc.limit_idx.push_back(position[static_cast<std::size_t>(i)]);
  qp_coords_ = std::move(qc);
}

}  // namespace lipmpcc::wbc

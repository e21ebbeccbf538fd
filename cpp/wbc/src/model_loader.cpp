// WbcModel construction: MJCF parsing (Pinocchio), frame and joint lookup, actuation matrix.
// This translation unit holds the Pinocchio MJCF parser only (the slowest header to compile).
#include <pinocchio/parsers/mjcf.hpp>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "lipmpcc/wbc/model.hpp"
#include "pinocchio_model.hpp"

namespace lipmpcc::wbc {

namespace {

pinocchio::Model parseMjcf(const std::string& path) {
  {
    std::ifstream probe(path);
    if (!probe.good()) throw std::invalid_argument("mjcf_path: cannot open '" + path + "'");
  }
  pinocchio::Model model;
  try {
    pinocchio::mjcf::buildModel(path, model);
    const bool free_root = model.njoints > 1 && model.joints[1].shortname() == "JointModelFreeFlyer";
    if (!free_root) {
      // Fixed-base file (root body without a free joint): add the floating base ourselves.
      model = pinocchio::Model();
      pinocchio::mjcf::buildModel(path, pinocchio::JointModelFreeFlyer(), model);
    }
  } catch (const std::exception& e) {
    throw std::runtime_error("mjcf_path: Pinocchio could not parse '" + path + "': " + e.what());
  }
  return model;
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
  holder->model = parseMjcf(spec.mjcf_path);
  pinocchio::Model& m = holder->model;
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
  if (!m.existFrame(spec.torso_body, pinocchio::BODY))
    throw std::invalid_argument("torso body: no body named '" + spec.torso_body +
                                "' in the MJCF model");
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

  // Unactuated rows: identity rows where B is zero, plus the left null space of the actuated rows
  // if actuators are coupled (rank deficient).
  std::vector<Eigen::Index> zero_rows, act_rows;
  for (Eigen::Index i = 0; i < nv_; ++i)
    (B_.row(i).cwiseAbs().maxCoeff() == 0.0 ? zero_rows : act_rows).push_back(i);
  const auto n_act = static_cast<Eigen::Index>(act_rows.size());
  Mat B_act(n_act, nu);
  for (Eigen::Index r = 0; r < n_act; ++r) B_act.row(r) = B_.row(act_rows[static_cast<std::size_t>(r)]);
  Eigen::JacobiSVD<Mat> svd(B_act, Eigen::ComputeFullU | Eigen::ComputeFullV);
  svd.setThreshold(1e-10);
  const Eigen::Index rank = svd.rank();
  const Eigen::Index n_extra_null = n_act - rank;
  N_T_ = Mat::Zero(static_cast<Eigen::Index>(zero_rows.size()) + n_extra_null, nv_);
  for (std::size_t r = 0; r < zero_rows.size(); ++r) N_T_(static_cast<Eigen::Index>(r), zero_rows[r]) = 1.0;
  for (Eigen::Index c = 0; c < n_extra_null; ++c) {
    const Eigen::Index row = static_cast<Eigen::Index>(zero_rows.size()) + c;
    for (Eigen::Index r = 0; r < n_act; ++r)
      N_T_(row, act_rows[static_cast<std::size_t>(r)]) = svd.matrixU()(r, rank + c);
  }
  B_pinv_ = B_.completeOrthogonalDecomposition().pseudoInverse();

  // Arm joints.
  for (const std::string& jn : spec.arm_joints) {
    const auto j = findJoint(m, jn, "arm_joints");
    requireOneDof(m, j, "arm_joints");
    arm_idx_q_.push_back(m.idx_qs[j]);
    arm_idx_v_.push_back(m.idx_vs[j]);
  }

  // Passive terms: damping from the MJCF, springs from the spec.
  damping_ = m.damping;
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
  q_neutral_ = Vec::Zero(nq_);
  q_neutral_[6] = 1.0;  // free-flyer quaternion (x, y, z, w)
  for (std::size_t i = 1; i < joint_idx_q_.size(); ++i)
    if (joint_nq_[i] == 4) q_neutral_[joint_idx_q_[i] + 3] = 1.0;  // spherical joints
  mass_ = 0.0;
  for (const auto& inertia : m.inertias) mass_ += inertia.mass();

  pin_ = std::move(holder);
}

}  // namespace lipmpcc::wbc

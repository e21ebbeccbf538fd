// One Pinocchio pass per tick: computeAllTerms (M, nle, joint Jacobians, centroidal map and its
// time variation, COM) then frame placements, frame Jacobians and drift accelerations.
#include <pinocchio/algorithm/compute-all-terms.hpp>
#include <pinocchio/algorithm/frames.hpp>

#include "lipmpcc/wbc/dynamics.hpp"
#include "pinocchio_model.hpp"

namespace lipmpcc::wbc {

DynamicsEvaluator::DynamicsEvaluator(const WbcModel& model)
    : model_(model), data_(std::make_unique<detail::PinocchioData>(model.pin().model)) {}

DynamicsEvaluator::~DynamicsEvaluator() = default;

void DynamicsEvaluator::compute(const Eigen::Ref<const Vec>& q, const Eigen::Ref<const Vec>& v,
                                DynamicsTerms& out) {
  const pinocchio::Model& m = model_.pin().model;
  pinocchio::Data& d = data_->data;
  const Eigen::Index nv = m.nv;

  pinocchio::computeAllTerms(m, d, q, v);  // data.a holds the drift (qdd = 0) accelerations
  pinocchio::updateFramePlacements(m, d);

  out.M = d.M;
  out.M.triangularView<Eigen::StrictlyLower>() = out.M.transpose();

  // h = C v + g - passive forces (MuJoCo applies -damping * v and spring torques).
  out.h = d.nle;
  out.h.array() += model_.damping().array() * v.array();
  const auto& sq = model_.springIdxQ();
  const auto& sv = model_.springIdxV();
  const auto& spec = model_.spec();
  for (std::size_t i = 0; i < sq.size(); ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    out.h[sv[i]] += spec.spring_stiffness[ii] * (q[sq[i]] - spec.spring_reference[ii]);
  }

  for (int f = 0; f < kNumFeet; ++f) {
    const auto fi = static_cast<std::size_t>(f);
    const auto fid = model_.soleFrame(f);
    out.J_sole[fi].setZero(6, nv);
    pinocchio::getFrameJacobian(m, d, fid, pinocchio::LOCAL_WORLD_ALIGNED, out.J_sole[fi]);
    out.vel_sole[fi] = pinocchio::getFrameVelocity(m, d, fid, pinocchio::LOCAL_WORLD_ALIGNED).toVector();
    out.drift_sole[fi] =
        pinocchio::getFrameClassicalAcceleration(m, d, fid, pinocchio::LOCAL_WORLD_ALIGNED).toVector();
    out.p_sole[fi] = d.oMf[fid].translation();
    out.R_sole[fi] = d.oMf[fid].rotation();
  }

  const auto tid = model_.torsoFrame();
  Mat6x& Jt = out.J_sole_scratch;
  Jt.setZero(6, nv);
  pinocchio::getFrameJacobian(m, d, tid, pinocchio::LOCAL_WORLD_ALIGNED, Jt);
  out.J_torso = Jt.bottomRows<3>();
  out.R_torso = d.oMf[tid].rotation();
  out.w_torso = pinocchio::getFrameVelocity(m, d, tid, pinocchio::LOCAL_WORLD_ALIGNED).angular();
  out.drift_torso =
      pinocchio::getFrameClassicalAcceleration(m, d, tid, pinocchio::LOCAL_WORLD_ALIGNED).angular();

  out.com = d.com[0];
  out.vcom = d.vcom[0];
  out.J_com = d.Jcom;
  out.drift_com.noalias() = d.dAg.topRows<3>() * v;
  out.drift_com /= d.mass[0];
  out.A_ang = d.Ag.bottomRows<3>();
  out.k_com.noalias() = out.A_ang * v;
  out.drift_k.noalias() = d.dAg.bottomRows<3>() * v;

  out.J_extra.resize(0, nv);
  out.gamma_extra.resize(0);
}

}  // namespace lipmpcc::wbc

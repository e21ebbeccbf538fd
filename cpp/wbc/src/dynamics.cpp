// One Pinocchio pass per tick: computeAllTerms (M, nle, joint Jacobians, centroidal map and its
// time variation, COM) then frame placements, frame Jacobians and drift accelerations (soles,
// torso, loop anchors).
#include <pinocchio/algorithm/center-of-mass.hpp>
#include <pinocchio/algorithm/compute-all-terms.hpp>
#include <pinocchio/algorithm/frames.hpp>

#include "lipmpcc/wbc/dynamics.hpp"
#include "pinocchio_model.hpp"

namespace lipmpcc::wbc {

DynamicsEvaluator::DynamicsEvaluator(const WbcModel& model)
    : model_(model),
      data_(std::make_unique<detail::PinocchioData>(model.pin().model)),
      // getFrameJacobian writes only the columns of the frame's supporting joints (with `=`, no
      // mimic joints): a buffer kept per frame needs its other columns zeroed once, not per tick.
      zero_once_(model.pin().model.mimicking_joints.empty()),
      J_anchor_(2 * model.loops().size(), Mat6x::Zero(6, model.pin().model.nv)) {}

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
    if (!zero_once_ || out.J_sole[fi].cols() != nv) out.J_sole[fi].setZero(6, nv);
    pinocchio::getFrameJacobian(m, d, fid, pinocchio::LOCAL_WORLD_ALIGNED, out.J_sole[fi]);
    out.vel_sole[fi] = pinocchio::getFrameVelocity(m, d, fid, pinocchio::LOCAL_WORLD_ALIGNED).toVector();
    out.drift_sole[fi] =
        pinocchio::getFrameClassicalAcceleration(m, d, fid, pinocchio::LOCAL_WORLD_ALIGNED).toVector();
    out.p_sole[fi] = d.oMf[fid].translation();
    out.R_sole[fi] = d.oMf[fid].rotation();
  }

  const auto tid = model_.torsoFrame();
  Mat6x& Jt = out.J_sole_scratch;  // the torso's Jacobian only (see zero_once_)
  if (!zero_once_ || Jt.cols() != nv) Jt.setZero(6, nv);
  pinocchio::getFrameJacobian(m, d, tid, pinocchio::LOCAL_WORLD_ALIGNED, Jt);
  out.J_torso = Jt.bottomRows<3>();
  out.R_torso = d.oMf[tid].rotation();
  out.w_torso = pinocchio::getFrameVelocity(m, d, tid, pinocchio::LOCAL_WORLD_ALIGNED).angular();
  out.drift_torso =
      pinocchio::getFrameClassicalAcceleration(m, d, tid, pinocchio::LOCAL_WORLD_ALIGNED).angular();

  out.com = d.com[0];
  out.vcom = d.vcom[0];
  out.J_com = d.Jcom;
  // COM drift: the COM acceleration at qdd = 0 from the joint accelerations of the pass (data.a
  // includes the motion-subspace bias of composite joints, which dAg v misses for a slide+ball base).
  pinocchio::centerOfMass(m, d, pinocchio::ACCELERATION, false);
  out.drift_com = d.acom[0];
  out.A_ang = d.Ag.bottomRows<3>();
  out.k_com.noalias() = out.A_ang * v;
  out.drift_k.noalias() = d.dAg.bottomRows<3>() * v;

  // Closed loops: relative position, velocity Jacobian and drift of the two anchors of each loop.
  const auto& loops = model_.loops();
  const auto nl = static_cast<Eigen::Index>(3 * loops.size());
  const auto nr = static_cast<Eigen::Index>(model_.nConstraintRows());
  out.J_loop.resize(nr, nv);
  out.gamma_loop.resize(nr);
  out.loop_residual.resize(nl);
  for (std::size_t k = 0; k < loops.size(); ++k) {
    const auto r = static_cast<Eigen::Index>(3 * k);
    const LoopClosure& c = loops[k];
    Mat6x& J1 = J_anchor_[2 * k];
    Mat6x& J2 = J_anchor_[2 * k + 1];
    if (!zero_once_) {
      J1.setZero();
      J2.setZero();
    }
    pinocchio::getFrameJacobian(m, d, c.frame1, pinocchio::LOCAL_WORLD_ALIGNED, J1);
    pinocchio::getFrameJacobian(m, d, c.frame2, pinocchio::LOCAL_WORLD_ALIGNED, J2);
    out.J_loop.middleRows<3>(r) = J1.topRows<3>() - J2.topRows<3>();
    out.gamma_loop.segment<3>(r) =
        pinocchio::getFrameClassicalAcceleration(m, d, c.frame1, pinocchio::LOCAL_WORLD_ALIGNED).linear() -
        pinocchio::getFrameClassicalAcceleration(m, d, c.frame2, pinocchio::LOCAL_WORLD_ALIGNED).linear();
    out.loop_residual.segment<3>(r) = d.oMf[c.frame1].translation() - d.oMf[c.frame2].translation();
  }
  // Rigid passive springs: qdd_s = 0.
  const auto& rigid = model_.rigidSprings();
  for (std::size_t k = 0; k < rigid.size(); ++k) {
    const Eigen::Index r = nl + static_cast<Eigen::Index>(k);
    out.J_loop.row(r).setZero();
    out.J_loop(r, sv[static_cast<std::size_t>(rigid[k])]) = 1.0;
    out.gamma_loop[r] = 0.0;
  }

  if (model_.spec().loop_formulation == LoopFormulation::kMultipliers && nr > 0) {
    out.J_extra = out.J_loop;
    out.gamma_extra = out.gamma_loop;
  } else {
    out.J_extra.resize(0, nv);
    out.gamma_extra.resize(0);
  }
  out.qdd_metric.resize(0, 0);
  out.qdd_metric_g.resize(0);
}

void DynamicsEvaluator::loopKinematics(const Eigen::Ref<const Vec>& q, Mat& J_loop, Vec& residual) {
  const pinocchio::Model& m = model_.pin().model;
  pinocchio::Data& d = data_->data;
  const Vec v = Vec::Zero(m.nv);
  pinocchio::computeAllTerms(m, d, q, v);
  pinocchio::updateFramePlacements(m, d);
  const auto& loops = model_.loops();
  J_loop.setZero(model_.nConstraintRows(), m.nv);
  residual.setZero(static_cast<Eigen::Index>(3 * loops.size()));
  const auto& rigid = model_.rigidSprings();
  for (std::size_t k = 0; k < rigid.size(); ++k)
    J_loop(static_cast<Eigen::Index>(3 * loops.size() + k), model_.springIdxV()[static_cast<std::size_t>(rigid[k])]) = 1.0;
  Mat6x J(6, m.nv);
  for (std::size_t k = 0; k < loops.size(); ++k) {
    const auto r = static_cast<Eigen::Index>(3 * k);
    J.setZero();
    pinocchio::getFrameJacobian(m, d, loops[k].frame1, pinocchio::LOCAL_WORLD_ALIGNED, J);
    J_loop.middleRows<3>(r) = J.topRows<3>();
    J.setZero();
    pinocchio::getFrameJacobian(m, d, loops[k].frame2, pinocchio::LOCAL_WORLD_ALIGNED, J);
    J_loop.middleRows<3>(r) -= J.topRows<3>();
    residual.segment<3>(r) = d.oMf[loops[k].frame1].translation() - d.oMf[loops[k].frame2].translation();
  }
}

}  // namespace lipmpcc::wbc

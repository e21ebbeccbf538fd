// Private: the Pinocchio objects behind WbcModel and DynamicsEvaluator.
// Included only by the Pinocchio translation units (model_loader.cpp, dynamics.cpp).
#pragma once

#include <pinocchio/multibody.hpp>

namespace lipmpcc::wbc::detail {

struct PinocchioModel {
  pinocchio::Model model;
};

struct PinocchioData {
  explicit PinocchioData(const pinocchio::Model& m) : data(m) {}
  pinocchio::Data data;
};

}  // namespace lipmpcc::wbc::detail

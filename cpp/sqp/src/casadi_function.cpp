// CasadiFunction: dlopen + CasADi's generated C interface (see casadi_function.hpp).
#include "lipmpcc/sqp/casadi_function.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <stdexcept>
#include <utility>

namespace lipmpcc::sqp {

namespace {

template <typename Fn>
Fn lookup(void* handle, const std::string& name, bool required = true) {
  void* p = dlsym(handle, name.c_str());
  if (p == nullptr && required) throw std::runtime_error("CasadiFunction: symbol " + name + " not found");
  return reinterpret_cast<Fn>(p);
}

}  // namespace

CasadiFunction::CasadiFunction(const std::string& path, const std::string& symbol) : path_(path), symbol_(symbol) {
  handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (handle_ == nullptr) {
    const char* err = dlerror();
    throw std::runtime_error("CasadiFunction: cannot load " + path + ": " + (err ? err : "unknown error"));
  }
  try {
    auto int_size = lookup<int (*)()>(handle_, symbol + "_casadi_int_size", false);
    if (int_size != nullptr && int_size() != static_cast<int>(sizeof(CasadiInt)))
      throw std::runtime_error("CasadiFunction: " + symbol + " uses another casadi_int size");
    eval_ = lookup<EvalFn>(handle_, symbol);
    auto n_in = lookup<CasadiInt (*)()>(handle_, symbol + "_n_in");
    auto n_out = lookup<CasadiInt (*)()>(handle_, symbol + "_n_out");
    auto sp_in = lookup<const CasadiInt* (*)(CasadiInt)>(handle_, symbol + "_sparsity_in");
    auto sp_out = lookup<const CasadiInt* (*)(CasadiInt)>(handle_, symbol + "_sparsity_out");
    auto work = lookup<int (*)(CasadiInt*, CasadiInt*, CasadiInt*, CasadiInt*)>(handle_, symbol + "_work");
    // Compressed sparsity pattern: nrow, ncol, 1 when dense; else nrow, ncol, colind[ncol + 1] (colind[0] = 0),
    // row[nnz] (a pattern with every entry is dense too)
    auto dense_size = [&](const CasadiInt* sp, const char* what, CasadiInt i) {
      const CasadiInt nrow = sp[0], ncol = sp[1], nnz = sp[2] == 1 ? nrow * ncol : sp[2 + ncol];
      if (nnz != nrow * ncol)
        throw std::runtime_error("CasadiFunction: " + symbol + " " + what + " " + std::to_string(i) + " is sparse");
      return std::make_pair(static_cast<int>(nrow), static_cast<int>(ncol));
    };
    for (CasadiInt i = 0; i < n_in(); ++i) {
      auto s = dense_size(sp_in(i), "input", i);
      in_sizes_.push_back(s.first * s.second);
    }
    for (CasadiInt j = 0; j < n_out(); ++j) {
      auto s = dense_size(sp_out(j), "output", j);
      out_sizes_.push_back(s.first * s.second);
      out_shapes_.push_back(s);
    }
    CasadiInt sz_arg = 0, sz_res = 0, sz_iw = 0, sz_w = 0;
    if (work(&sz_arg, &sz_res, &sz_iw, &sz_w) != 0) throw std::runtime_error("CasadiFunction: " + symbol + "_work failed");
    arg_.assign(static_cast<std::size_t>(std::max<CasadiInt>(sz_arg, n_in())), nullptr);
    res_.assign(static_cast<std::size_t>(std::max<CasadiInt>(sz_res, n_out())), nullptr);
    iw_.assign(static_cast<std::size_t>(sz_iw), 0);
    w_.assign(static_cast<std::size_t>(sz_w), 0.0);
    if (auto incref = lookup<void (*)()>(handle_, symbol + "_incref", false)) incref();
    decref_ = lookup<void (*)()>(handle_, symbol + "_decref", false);
    if (auto checkout = lookup<int (*)()>(handle_, symbol + "_checkout", false)) mem_ = checkout();
    release_ = lookup<void (*)(int)>(handle_, symbol + "_release", false);
  } catch (...) {
    dlclose(handle_);
    throw;
  }
}

CasadiFunction::CasadiFunction(std::vector<int> in_sizes, std::vector<std::pair<int, int>> out_shapes, Callback callback,
                               const std::string& name)
    : callback_(std::move(callback)), symbol_(name), in_sizes_(std::move(in_sizes)), out_shapes_(std::move(out_shapes)) {
  if (!callback_) throw std::invalid_argument("CasadiFunction: " + name + " needs a callback");
  for (int n : in_sizes_)
    if (n < 0) throw std::invalid_argument("CasadiFunction: " + name + " has an input of negative size");
  for (const auto& s : out_shapes_) {
    if (s.first < 0 || s.second < 0) throw std::invalid_argument("CasadiFunction: " + name + " has an output of negative size");
    out_sizes_.push_back(s.first * s.second);
  }
}

CasadiFunction::~CasadiFunction() {
  if (handle_ == nullptr) return;  // a callback
  if (release_ != nullptr) release_(mem_);
  if (decref_ != nullptr) decref_();
  dlclose(handle_);
}

void CasadiFunction::eval(const double* const* args, double* const* res) {
  if (callback_) {
    callback_(args, res);
    return;
  }
  for (std::size_t i = 0; i < in_sizes_.size(); ++i) arg_[i] = args[i];
  for (std::size_t j = 0; j < out_sizes_.size(); ++j) res_[j] = res[j];
  if (eval_(arg_.data(), res_.data(), iw_.data(), w_.data(), mem_) != 0)
    throw std::runtime_error("CasadiFunction: " + symbol_ + " returned an error");
}

}  // namespace lipmpcc::sqp

// A CasADi-generated C function loaded from a shared library (dlopen) and called through CasADi's C
// interface: <name>(arg, res, iw, w, mem), <name>_work, <name>_n_in / _n_out, <name>_sparsity_in /
// _out, <name>_checkout / _release, <name>_incref / _decref, <name>_casadi_int_size. Or a callback with the
// same calling convention (an interpreted CasADi function evaluated by Python while its library is compiled).
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace lipmpcc::sqp {

/// One function of a library written by CasADi's CodeGenerator (lipmpcc.solvers.casadi_buffer's JIT
/// cache). Every input and output must be dense; inputs and outputs are column-major arrays of
/// ``in_size(i)`` / ``out_size(j)`` doubles. Not thread-safe (one working memory per object).
class CasadiFunction {
 public:
  /// Evaluates ``args[i]`` (inSize(i) doubles) into ``res[j]`` (outSize(j) doubles), as the generated C does.
  using Callback = std::function<void(const double* const* args, double* const* res)>;

  /// Loads ``symbol`` from the library at ``path``; throws std::runtime_error when the library or one
  /// of the C interface's symbols is missing, the integer type differs or an input/output is sparse.
  CasadiFunction(const std::string& path, const std::string& symbol);
  /// The function evaluated by ``callback`` (inputs of ``in_sizes`` doubles, outputs of ``out_shapes``, named
  /// ``name``); throws std::invalid_argument for an empty callback or a negative size.
  CasadiFunction(std::vector<int> in_sizes, std::vector<std::pair<int, int>> out_shapes, Callback callback,
                 const std::string& name);
  ~CasadiFunction();
  CasadiFunction(const CasadiFunction&) = delete;
  CasadiFunction& operator=(const CasadiFunction&) = delete;

  int nIn() const { return static_cast<int>(in_sizes_.size()); }
  int nOut() const { return static_cast<int>(out_sizes_.size()); }
  int inSize(int i) const { return in_sizes_.at(static_cast<std::size_t>(i)); }
  int outSize(int j) const { return out_sizes_.at(static_cast<std::size_t>(j)); }
  /// (rows, columns) of output ``j``.
  std::pair<int, int> outShape(int j) const { return out_shapes_.at(static_cast<std::size_t>(j)); }
  const std::string& path() const { return path_; }
  const std::string& symbol() const { return symbol_; }
  /// Whether it is evaluated by a callback (no library loaded).
  bool isCallback() const { return static_cast<bool>(callback_); }

  /// Evaluates with ``args[i]`` pointing at inSize(i) doubles and ``res[j]`` at outSize(j) doubles
  /// (a null result is not computed). Throws std::runtime_error when the function reports an error.
  void eval(const double* const* args, double* const* res);

 private:
  using CasadiInt = long long;
  using EvalFn = int (*)(const double**, double**, CasadiInt*, double*, int);

  Callback callback_;
  void* handle_ = nullptr;
  EvalFn eval_ = nullptr;
  void (*release_)(int) = nullptr;
  void (*decref_)() = nullptr;
  int mem_ = 0;
  std::string path_, symbol_;
  std::vector<int> in_sizes_, out_sizes_;
  std::vector<std::pair<int, int>> out_shapes_;
  std::vector<const double*> arg_;
  std::vector<double*> res_;
  std::vector<CasadiInt> iw_;
  std::vector<double> w_;
};

}  // namespace lipmpcc::sqp

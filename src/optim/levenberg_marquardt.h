#pragma once
// The Levenberg-Marquardt loop shared by the optimisers in optim/, with Ceres' strategy and
// defaults: damping lambda * clamp(diag(H), 1e-6, 1e32) starting at lambda = 1e-4; a step is
// accepted when the cost falls by more than 1e-3 of the decrease the quadratic model predicts;
// then lambda *= max(1/3, 1 - (2 rho - 1)^3), otherwise lambda grows by a factor that doubles
// with each rejection in a row. An iteration is one linear solve, accepted or not. Converged
// when an accepted step changes the cost by at most function_tolerance * cost, or a step is at
// most parameter_tolerance * (|x| + parameter_tolerance).
//
// `Problem` supplies (cost = 0.5 * sum of robustified squared whitened residuals):
//   using State; using Linearization; using Step;
//   bool Linearize(const State&, Linearization*) const;   // false: not evaluable there
//   double CostOf(const Linearization&) const;
//   bool Solve(const Linearization&, double lambda, Step*, double* model_decrease) const;
//   bool StepIsTiny(const State&, const Step&, double tolerance) const;
//   State Apply(const State&, const Step&) const;
//   double Cost(const State&) const;                        // +inf: not evaluable there

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>

namespace esdslam {

struct LmControl {
  int max_iterations = 10;
  double function_tolerance = 1e-6;
  double parameter_tolerance = 1e-8;
};

struct LmOutcome {
  double initial_cost = 0;
  double final_cost = 0;
  int iterations = 0;    // linear solves done
  bool stopped = false;  // ended by the stop flag (the state is the best so far)
  bool evaluable = true; // false: the start itself could not be evaluated (state unchanged)
};

namespace lm_detail {
constexpr double kInitialLambda = 1e-4;
constexpr double kMaxLambda = 1e32;
constexpr double kMinRelativeDecrease = 1e-3;
}  // namespace lm_detail

// Huber's rho(s) for a squared whitened residual s with threshold delta (+inf: plain least
// squares, rho(s) = s); *weight = rho'(s), the weight of iteratively reweighted least squares.
inline double HuberRho(double s, double delta, double* weight) {
  *weight = 1;
  if (!(s > delta * delta)) return s;
  const double root = std::sqrt(s);
  *weight = delta / root;
  return 2 * delta * root - delta * delta;
}

// Damping term lambda * clamp(diag(h)) of one diagonal block.
template <class Matrix>
auto LmDamping(const Matrix& h, double lambda) {
  return (lambda * h.diagonal().cwiseMax(1e-6).cwiseMin(1e32)).eval();
}

template <class Problem>
LmOutcome MinimizeLm(const Problem& problem, const LmControl& control, const std::atomic<bool>* stop,
                     typename Problem::State* state) {
  LmOutcome outcome;
  typename Problem::Linearization linearization;
  if (!problem.Linearize(*state, &linearization)) {
    outcome.evaluable = false;
    return outcome;
  }
  outcome.initial_cost = outcome.final_cost = problem.CostOf(linearization);
  double lambda = lm_detail::kInitialLambda, growth = 2;
  while (outcome.iterations < control.max_iterations && lambda <= lm_detail::kMaxLambda) {
    if (stop != nullptr && stop->load()) {
      outcome.stopped = true;
      break;
    }
    ++outcome.iterations;
    typename Problem::Step step;
    double model_decrease = 0;
    const bool solved = problem.Solve(linearization, lambda, &step, &model_decrease);
    if (solved && problem.StepIsTiny(*state, step, control.parameter_tolerance)) break;
    const double cost = outcome.final_cost;
    typename Problem::State candidate;
    double new_cost = std::numeric_limits<double>::infinity();
    if (solved && model_decrease > 0) {
      candidate = problem.Apply(*state, step);
      new_cost = problem.Cost(candidate);
    }
    if (!std::isfinite(new_cost) || !((cost - new_cost) > lm_detail::kMinRelativeDecrease * model_decrease)) {
      lambda *= growth;  // rejected: more damping, the same linearization
      growth *= 2;
      continue;
    }
    const double relative_decrease = (cost - new_cost) / model_decrease;
    *state = std::move(candidate);
    if (!problem.Linearize(*state, &linearization)) break;  // cannot happen: its cost was finite
    outcome.final_cost = problem.CostOf(linearization);
    lambda *= std::max(1.0 / 3.0, 1.0 - std::pow(2 * relative_decrease - 1, 3));
    growth = 2;
    if (cost - outcome.final_cost <= control.function_tolerance * cost) break;
  }
  return outcome;
}

}  // namespace esdslam

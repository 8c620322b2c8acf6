#include "wbc/task_stack.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace ballast::wbc {

TaskStack::TaskStack(int variables, int maxLevels, int maxEqualityRows, int maxInequalityRows)
    : n_(variables), maxLevels_(maxLevels) {
  if (variables < 1 || maxLevels < 1 || maxEqualityRows < 0 || maxInequalityRows < 0)
    throw std::invalid_argument("TaskStack: needs variables and levels");
  A_.setZero(std::max(maxEqualityRows, 1), n_);
  b_.setZero(std::max(maxEqualityRows, 1));
  D_.setZero(std::max(maxInequalityRows, 1), n_);
  lower_.setZero(std::max(maxInequalityRows, 1));
  upper_.setZero(std::max(maxInequalityRows, 1));
  levelEq_.reserve(maxLevels + 1);
  levelIneq_.reserve(maxLevels + 1);
  clear();
}

void TaskStack::clear() {
  levelEq_.assign(1, 0);
  levelIneq_.assign(1, 0);
}

int TaskStack::beginLevel() {
  if (levels() >= maxLevels_)
    throw std::length_error("TaskStack: more than " + std::to_string(maxLevels_) + " levels");
  levelEq_.push_back(levelEq_.back());  // within the reserved capacity: no allocation
  levelIneq_.push_back(levelIneq_.back());
  return levels() - 1;
}

TaskStack::EqualityRows TaskStack::addEqualities(int rows) {
  const int begin = levelEq_.back();
  if (levels() == 0 || rows < 0 || begin + rows > maxEqualityRows())
    throw std::length_error("TaskStack: equality rows beyond the capacity of " +
                            std::to_string(maxEqualityRows()) + " (or no level open)");
  levelEq_.back() += rows;
  auto A = A_.middleRows(begin, rows);
  auto b = b_.segment(begin, rows);
  A.setZero();
  b.setZero();
  return {A, b};
}

TaskStack::InequalityRows TaskStack::addInequalities(int rows) {
  const int begin = levelIneq_.back();
  if (levels() == 0 || rows < 0 || begin + rows > maxInequalityRows())
    throw std::length_error("TaskStack: inequality rows beyond the capacity of " +
                            std::to_string(maxInequalityRows()) + " (or no level open)");
  levelIneq_.back() += rows;
  auto D = D_.middleRows(begin, rows);
  auto lo = lower_.segment(begin, rows);
  auto hi = upper_.segment(begin, rows);
  D.setZero();
  lo.setConstant(-std::numeric_limits<double>::infinity());
  hi.setConstant(std::numeric_limits<double>::infinity());
  return {D, lo, hi};
}

double TaskStack::residual(int k, const Eigen::VectorXd& x) const {
  double sum = 0.0;
  for (int i = equalityBegin(k); i < equalityBegin(k) + equalityRows(k); ++i) {
    const double r = A_.row(i).dot(x) - b_[i];
    sum += r * r;
  }
  return std::sqrt(sum);
}

double TaskStack::violation(int k, const Eigen::VectorXd& x) const {
  double worst = 0.0;
  for (int i = inequalityBegin(k); i < inequalityBegin(k) + inequalityRows(k); ++i) {
    const double v = D_.row(i).dot(x);
    worst = std::max({worst, lower_[i] - v, v - upper_[i]});
  }
  return worst;
}

}  // namespace ballast::wbc

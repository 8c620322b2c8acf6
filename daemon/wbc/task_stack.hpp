// A stack of priority levels over one decision vector x (n), the input of the hierarchical and
// weighted solvers (hierarchical_qp.hpp). Level 0 has the highest priority. Each level holds
//   equality-task rows    A_k x ≈ b_k          (met in the least-squares sense)
//   inequality rows       lower_k ≤ D_k x ≤ upper_k   (±∞ for an absent side)
// Rows are appended level by level into storage sized at construction: filling a stack every
// control tick allocates nothing.
#pragma once

#include <stdexcept>
#include <vector>

#include <Eigen/Core>

namespace ballast::wbc {

class TaskStack {
 public:
  struct EqualityRows {
    Eigen::Block<Eigen::MatrixXd> A;
    Eigen::VectorBlock<Eigen::VectorXd> b;
  };
  struct InequalityRows {
    Eigen::Block<Eigen::MatrixXd> D;
    Eigen::VectorBlock<Eigen::VectorXd> lower;
    Eigen::VectorBlock<Eigen::VectorXd> upper;
  };

  /// Capacity: levels, and equality and inequality rows summed over all levels.
  TaskStack(int variables, int maxLevels, int maxEqualityRows, int maxInequalityRows);

  /// Removes every level.
  void clear();
  /// Opens the next (lower-priority) level; returns its index. Throws std::length_error past the
  /// capacity (a programming error: capacities are fixed by the task layout).
  int beginLevel();
  /// Appends rows to the current level, zeroed (A = 0, b = 0).
  EqualityRows addEqualities(int rows);
  /// Appends rows to the current level, zeroed with unbounded sides (D = 0, lower = −∞, upper = +∞).
  InequalityRows addInequalities(int rows);

  int variables() const { return n_; }
  int levels() const { return static_cast<int>(levelEq_.size()) - 1; }
  int maxLevels() const { return maxLevels_; }
  int maxEqualityRows() const { return static_cast<int>(A_.rows()); }
  int maxInequalityRows() const { return static_cast<int>(D_.rows()); }

  // Level k's rows are equalityBegin(k) .. equalityBegin(k + 1) − 1 of A()/b(), and likewise for
  // the inequalities; the levels' rows are contiguous and in priority order.
  int equalityBegin(int k) const { return levelEq_[k]; }
  int equalityRows(int k) const { return levelEq_[k + 1] - levelEq_[k]; }
  int inequalityBegin(int k) const { return levelIneq_[k]; }
  int inequalityRows(int k) const { return levelIneq_[k + 1] - levelIneq_[k]; }
  int totalEqualityRows() const { return levelEq_.back(); }
  int totalInequalityRows() const { return levelIneq_.back(); }

  const Eigen::MatrixXd& A() const { return A_; }
  const Eigen::VectorXd& b() const { return b_; }
  const Eigen::MatrixXd& D() const { return D_; }
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }

  /// ‖A_k x − b_k‖ (Euclidean).
  double residual(int k, const Eigen::VectorXd& x) const;
  /// Largest violation of level k's inequality rows by x (0 if all hold).
  double violation(int k, const Eigen::VectorXd& x) const;

 private:
  int n_;
  int maxLevels_;
  Eigen::MatrixXd A_, D_;
  Eigen::VectorXd b_, lower_, upper_;
  std::vector<int> levelEq_, levelIneq_;  // begin offsets, one past the last level at the back
};

}  // namespace ballast::wbc

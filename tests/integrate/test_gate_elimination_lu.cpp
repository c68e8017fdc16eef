// The structured direct solver for CVODE's Newton matrix against Eigen's full
// LU: gate rows eliminated first must give the same solution as a dense solve.
#include <doctest/doctest.h>

#include <Eigen/Dense>
#include <random>

#include "integrate/gate_elimination_lu.hpp"

using namespace fibrodem;

namespace {

// A Newton matrix shaped like a cell model's: row 0 (V) and a few
// concentration rows full; gate rows with a diagonal >= 1 and one entry in
// column 0 or in a concentration's column; a state with no coupling at all; and
// two rows that point at each other (neither may be eliminated on the other).
Eigen::MatrixXd cell_like_matrix(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const int n = 21;
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < 5; ++i)  // V and four concentrations
    for (int j = 0; j < n; ++j) m(i, j) = 50 * u(rng);
  for (int i = 0; i < 5; ++i) m(i, i) += 200;
  for (int j = 5; j < n; ++j) {
    m(j, j) = 1 + 30 * std::abs(u(rng));
    m(j, j == 7 ? 3 : 0) = 5 * u(rng);  // row 7 rides on a concentration
  }
  m(9, 0) = 0;  // no coupling: a pure diagonal row
  m(11, 0) = 0;
  m(11, 12) = 0.3;  // rows 11 and 12 point at each other
  m(12, 0) = 0;
  m(12, 11) = -0.2;
  return m;
}

double relative_error(GateEliminationLu& lu, const Eigen::MatrixXd& m, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd r(m.rows());
  for (int i = 0; i < r.size(); ++i) r(i) = u(rng);
  Eigen::VectorXd x = r;
  lu.solve(x.data());
  const Eigen::VectorXd exact = m.fullPivLu().solve(r);
  return (x - exact).norm() / exact.norm();
}

}  // namespace

TEST_CASE("gate elimination LU solves a cell-shaped Newton matrix like a full LU") {
  std::mt19937 rng(7);
  GateEliminationLu lu(21);
  for (int trial = 0; trial < 20; ++trial) {
    const Eigen::MatrixXd m = cell_like_matrix(rng);
    REQUIRE(lu.factor(m.data()));
    // 16 gate-shaped rows, less one of the pair that points at each other.
    CHECK(lu.eliminated() == 15);
    CHECK(relative_error(lu, m, rng) < 1e-12);
  }
}

TEST_CASE("gate elimination LU on a full matrix is a plain LU with pivoting") {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd m(9, 9);
  for (int i = 0; i < 9; ++i)
    for (int j = 0; j < 9; ++j) m(i, j) = u(rng);
  m(0, 0) = 0;  // needs a row swap
  GateEliminationLu lu(9);
  REQUIRE(lu.factor(m.data()));
  CHECK(lu.eliminated() == 0);
  CHECK(relative_error(lu, m, rng) < 1e-12);
}

TEST_CASE("gate elimination LU reports a singular matrix") {
  // Rows 0 and 1 are [0.25 0.5; 0.25 d]: row 0's pivot is too small to
  // eliminate it, row 1 is eliminated onto column 0, leaving 0.25 - 0.125 / d.
  Eigen::MatrixXd m = Eigen::MatrixXd::Identity(4, 4);
  m(0, 0) = 0.25;
  m(0, 1) = 0.5;
  m(1, 0) = 0.25;
  m(1, 1) = 1.0;
  GateEliminationLu lu(4);
  REQUIRE(lu.factor(m.data()));
  CHECK(lu.eliminated() == 3);
  std::mt19937 rng(3);
  CHECK(relative_error(lu, m, rng) < 1e-12);
  m(1, 1) = 0.5;  // singular
  CHECK_FALSE(lu.factor(m.data()));
}

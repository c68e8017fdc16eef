// fibrodem's compiled CVODE vector operations give, bit for bit, what
// SUNDIALS' own serial operations (N_V*_Serial, called directly here) give,
// in every special case the library distinguishes.
#include <doctest/doctest.h>

#include <sundials/sundials_context.h>

#include <cstring>
#include <random>
#include <vector>

#include "integrate/cvode_vector_ops.hpp"

using namespace fibrodem;

namespace {

struct Vectors {
  SUNContext sun = nullptr;
  std::vector<N_Vector> v;  // the library's ops
  std::vector<N_Vector> w;  // ours, same values
  static constexpr sunindextype kLength = 31;  // Ni 2017's states: not a multiple of a SIMD width

  Vectors() {
    SUNContext_Create(nullptr, &sun);
    std::mt19937_64 random(20261127);
    std::uniform_real_distribution<double> value(-3.0, 3.0);
    for (int k = 0; k < 4; ++k) {
      v.push_back(N_VNew_Serial(kLength, sun));
      w.push_back(N_VNew_Serial(kLength, sun));
      use_compiled_vector_ops(w.back());
      for (sunindextype i = 0; i < kLength; ++i) NV_Ith_S(v[k], i) = NV_Ith_S(w[k], i) = value(random);
    }
  }
  ~Vectors() {
    for (auto x : v) N_VDestroy(x);
    for (auto x : w) N_VDestroy(x);
    SUNContext_Free(&sun);
  }
  // Vector k of the library's set equals vector k of ours, bit for bit.
  bool same(int k) const {
    return std::memcmp(NV_DATA_S(v[k]), NV_DATA_S(w[k]), sizeof(double) * kLength) == 0;
  }
  bool same(double a, double b) const { return std::memcmp(&a, &b, sizeof a) == 0; }
};

}  // namespace

TEST_CASE("compiled CVODE vector operations: N_VLinearSum as the library, case by case") {
  const double c = 0.7310585786300049, d = -1.3862943611198906;
  const double pairs[][2] = {{1, 1}, {1, -1}, {-1, 1}, {1, c}, {c, 1}, {-1, c}, {c, -1}, {c, c}, {c, -c}, {c, d}};
  for (const auto& ab : pairs) {
    Vectors s;
    CAPTURE(ab[0]);
    CAPTURE(ab[1]);
    N_VLinearSum_Serial(ab[0], s.v[0], ab[1], s.v[1], s.v[2]);
    N_VLinearSum(ab[0], s.w[0], ab[1], s.w[1], s.w[2]);
    CHECK(s.same(2));
  }
  // In place: y <- a x + y (b = 1) and x <- x + b y (a = 1), a or b 1, -1 or other.
  for (double a : {1.0, -1.0, c}) {
    Vectors s;
    CAPTURE(a);
    N_VLinearSum_Serial(a, s.v[0], 1.0, s.v[1], s.v[1]);
    N_VLinearSum(a, s.w[0], 1.0, s.w[1], s.w[1]);
    CHECK(s.same(1));
    N_VLinearSum_Serial(1.0, s.v[2], a, s.v[3], s.v[2]);
    N_VLinearSum(1.0, s.w[2], a, s.w[3], s.w[2]);
    CHECK(s.same(2));
  }
}

TEST_CASE("compiled CVODE vector operations: element-wise operations and norms as the library") {
  Vectors s;
  const double c = 2.718281828459045;
  N_VScale_Serial(c, s.v[0], s.v[1]);
  N_VScale(c, s.w[0], s.w[1]);
  CHECK(s.same(1));
  N_VScale_Serial(-1.0, s.v[0], s.v[2]);
  N_VScale(-1.0, s.w[0], s.w[2]);
  CHECK(s.same(2));
  N_VScale_Serial(1.0, s.v[1], s.v[3]);
  N_VScale(1.0, s.w[1], s.w[3]);
  CHECK(s.same(3));
  N_VScale_Serial(c, s.v[3], s.v[3]);
  N_VScale(c, s.w[3], s.w[3]);
  CHECK(s.same(3));
  N_VProd_Serial(s.v[0], s.v[1], s.v[2]);
  N_VProd(s.w[0], s.w[1], s.w[2]);
  CHECK(s.same(2));
  N_VDiv_Serial(s.v[0], s.v[1], s.v[2]);
  N_VDiv(s.w[0], s.w[1], s.w[2]);
  CHECK(s.same(2));
  N_VAbs_Serial(s.v[0], s.v[2]);
  N_VAbs(s.w[0], s.w[2]);
  CHECK(s.same(2));
  N_VInv_Serial(s.v[0], s.v[2]);
  N_VInv(s.w[0], s.w[2]);
  CHECK(s.same(2));
  N_VAddConst_Serial(s.v[0], c, s.v[2]);
  N_VAddConst(s.w[0], c, s.w[2]);
  CHECK(s.same(2));
  N_VCompare_Serial(1.5, s.v[0], s.v[2]);
  N_VCompare(1.5, s.w[0], s.w[2]);
  CHECK(s.same(2));
  CHECK(s.same(N_VDotProd_Serial(s.v[0], s.v[1]), N_VDotProd(s.w[0], s.w[1])));
  CHECK(s.same(N_VMaxNorm_Serial(s.v[0]), N_VMaxNorm(s.w[0])));
  CHECK(s.same(N_VWrmsNorm_Serial(s.v[0], s.v[1]), N_VWrmsNorm(s.w[0], s.w[1])));
  CHECK(s.same(N_VMin_Serial(s.v[0]), N_VMin(s.w[0])));
  // The inverse test with a zero entry: false, the other entries inverted.
  NV_Ith_S(s.v[0], 3) = NV_Ith_S(s.w[0], 3) = 0.0;
  N_VConst_Serial(5.0, s.v[2]);
  N_VConst(5.0, s.w[2]);
  CHECK(s.same(2));
  CHECK(N_VInvTest_Serial(s.v[0], s.v[2]) == SUNFALSE);
  CHECK(N_VInvTest(s.w[0], s.w[2]) == SUNFALSE);
  CHECK(s.same(2));
}

TEST_CASE("compiled CVODE vector operations pass to clones, as CVODE's work vectors are made") {
  Vectors s;
  N_Vector clone = N_VClone(s.w[0]);
  const bool ours = clone->ops->nvlinearsum == s.w[0]->ops->nvlinearsum;
  const bool library = clone->ops->nvlinearsum == s.v[0]->ops->nvlinearsum;
  CHECK(ours);
  CHECK_FALSE(library);
  N_VDestroy(clone);
}

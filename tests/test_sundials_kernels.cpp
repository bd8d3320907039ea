// core/sundials_kernels: the vector and dense-matrix operations put in place of SUNDIALS' give
// the library's results bit for bit (each special case of N_VLinearSum, aliasing, the fused
// operations against SUNDIALS' fallbacks), and the dense LU solves and reports what cannot be
// factorised.
#include <sundials/sundials_context.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

#include "core/sundials_kernels.hpp"

namespace {

using rodend::detail::make_dense_lu;
using rodend::detail::use_fast_ops;

constexpr sunindextype kN = 31;  // rod-end-kinematic's states with wear

struct Context {
  SUNContext ctx = nullptr;
  Context() { SUNContext_Create(nullptr, &ctx); }
  ~Context() { SUNContext_Free(&ctx); }
};

/// k vectors with the library's operations and k with ours, holding the same values of mixed
/// magnitude and sign
struct VectorPairs {
  std::vector<N_Vector> lib, fast;
  VectorPairs(SUNContext ctx, int k) {
    std::mt19937 rng(34);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int j = 0; j < k; ++j) {
      lib.push_back(N_VNew_Serial(kN, ctx));
      fast.push_back(N_VNew_Serial(kN, ctx));
      use_fast_ops(fast.back());
      for (sunindextype i = 0; i < kN; ++i)
        NV_Ith_S(lib[j], i) = NV_Ith_S(fast[j], i) = u(rng) * std::pow(10.0, 6.0 * u(rng));
    }
  }
  ~VectorPairs() {
    for (N_Vector v : lib) N_VDestroy(v);
    for (N_Vector v : fast) N_VDestroy(v);
  }
  /// every value of every pair the same, bit for bit
  bool same() const {
    for (std::size_t j = 0; j < lib.size(); ++j)
      if (std::memcmp(N_VGetArrayPointer(lib[j]), N_VGetArrayPointer(fast[j]),
                      kN * sizeof(double)) != 0)
        return false;
    return true;
  }
};

const double kCoefficients[] = {1.0, -1.0, 0.3, -0.3, 2.5, 0.0};

}  // namespace

TEST_CASE("sundials kernels: linear sums bit-identical to the library's", "[sundials]") {
  Context c;
  // every (a, b) of the coefficients (the equal, opposite and +-1 cases) and each aliasing of
  // the result: z apart, z = x, z = y
  for (double a : kCoefficients)
    for (double b : kCoefficients)
      for (int alias = 0; alias < 3; ++alias) {
        VectorPairs v(c.ctx, 3);
        auto run = [&](std::vector<N_Vector>& w) {
          N_Vector z = alias == 0 ? w[2] : alias == 1 ? w[0] : w[1];
          N_VLinearSum(a, w[0], b, w[1], z);
        };
        run(v.lib);
        run(v.fast);
        INFO("a = " << a << ", b = " << b << ", alias " << alias);
        CHECK(v.same());
      }
}

TEST_CASE("sundials kernels: scale and element-wise operations bit-identical", "[sundials]") {
  Context c;
  for (double s : kCoefficients)
    for (int in_place = 0; in_place < 2; ++in_place) {
      VectorPairs v(c.ctx, 2);
      for (auto* w : {&v.lib, &v.fast}) N_VScale(s, (*w)[0], (*w)[in_place ? 0 : 1]);
      INFO("c = " << s << (in_place ? ", in place" : ""));
      CHECK(v.same());
    }
  VectorPairs v(c.ctx, 4);
  for (auto* w : {&v.lib, &v.fast}) {
    N_VAbs((*w)[0], (*w)[1]);
    N_VInv((*w)[1], (*w)[2]);
    N_VAddConst((*w)[2], 0.7, (*w)[3]);
    N_VProd((*w)[3], (*w)[0], (*w)[1]);
    N_VDiv((*w)[1], (*w)[2], (*w)[2]);
  }
  CHECK(v.same());
  const double lib = N_VWrmsNorm(v.lib[0], v.lib[3]), fast = N_VWrmsNorm(v.fast[0], v.fast[3]);
  CHECK(std::memcmp(&lib, &fast, sizeof lib) == 0);
  for (auto* w : {&v.lib, &v.fast}) N_VConst(-2.0, (*w)[0]);
  CHECK(v.same());
}

TEST_CASE("sundials kernels: fused operations as SUNDIALS' fallbacks", "[sundials]") {
  Context c;
  double coef[] = {0.3, 1.0, -1.0, -2.5};
  // z apart from the terms, z the first term, z a later term (the fallback's partial sum)
  for (int nvec = 1; nvec <= 4; ++nvec)
    for (int z_at : {4, 0, 2}) {
      if (z_at != 4 && z_at >= nvec) continue;
      VectorPairs v(c.ctx, 5);
      for (auto* w : {&v.lib, &v.fast}) N_VLinearCombination(nvec, coef, w->data(), (*w)[z_at]);
      INFO("nvec " << nvec << ", z = vector " << z_at);
      CHECK(v.same());
    }
  // Z_i = a_i x + Y_i with Z_0 the x of the later ones
  VectorPairs v(c.ctx, 6);
  for (auto* w : {&v.lib, &v.fast}) {
    N_Vector Y[] = {(*w)[1], (*w)[2], (*w)[3]}, Z[] = {(*w)[0], (*w)[4], (*w)[3]};
    N_VScaleAddMulti(3, coef, (*w)[0], Y, Z);
  }
  CHECK(v.same());
}

TEST_CASE("sundials kernels: dense matrix operations bit-identical", "[sundials]") {
  Context c;
  SUNMatrix lib = SUNDenseMatrix(kN, kN, c.ctx), fast = SUNDenseMatrix(kN, kN, c.ctx);
  use_fast_ops(fast);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (sunindextype i = 0; i < kN * kN; ++i)
    SUNDenseMatrix_Data(lib)[i] = SUNDenseMatrix_Data(fast)[i] = u(rng);
  SUNMatrix lib_copy = SUNMatClone(lib), fast_copy = SUNMatClone(fast);
  CHECK(fast_copy->ops->copy == fast->ops->copy);  // a clone (the saved Jacobian) is ours too
  SUNMatCopy(lib, lib_copy);
  SUNMatCopy(fast, fast_copy);
  SUNMatScaleAddI(-0.37, lib_copy);
  SUNMatScaleAddI(-0.37, fast_copy);
  const auto bytes = static_cast<std::size_t>(kN * kN) * sizeof(double);
  CHECK(std::memcmp(SUNDenseMatrix_Data(lib_copy), SUNDenseMatrix_Data(fast_copy), bytes) == 0);
  SUNMatZero(fast_copy);
  for (sunindextype i = 0; i < kN * kN; ++i) CHECK(SUNDenseMatrix_Data(fast_copy)[i] == 0.0);
  for (SUNMatrix m : {lib, fast, lib_copy, fast_copy}) SUNMatDestroy(m);
}

TEST_CASE("sundials kernels: the dense LU solves a pivoting system and flags singular ones",
          "[sundials]") {
  Context c;
  SUNMatrix A = SUNDenseMatrix(kN, kN, c.ctx), A0 = SUNDenseMatrix(kN, kN, c.ctx);
  SUNLinearSolver S = make_dense_lu(c.ctx);
  REQUIRE(S);
  // I - gamma J of a sparse J (a third of it non-zero) whose last three columns are zero (the
  // audit states), and a zero at (0, 0): without row swaps the factorisation would divide by 0
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double* a = SUNDenseMatrix_Data(A);
  for (sunindextype j = 0; j < kN; ++j)
    for (sunindextype i = 0; i < kN; ++i) {
      const double J = (j < kN - 3 && u(rng) > 0.33) ? 50.0 * u(rng) : 0.0;
      a[j * kN + i] = (i == j ? 1.0 : 0.0) - 0.01 * J;
    }
  a[0] = 0.0;
  SUNMatCopy(A, A0);
  REQUIRE(SUNLinSolSetup(S, A) == SUNLS_SUCCESS);
  N_Vector b = N_VNew_Serial(kN, c.ctx), x = N_VNew_Serial(kN, c.ctx);
  for (sunindextype i = 0; i < kN; ++i) NV_Ith_S(b, i) = u(rng);
  REQUIRE(SUNLinSolSolve(S, A, x, b, 0.0) == SUNLS_SUCCESS);
  // backward stable: the residual is a few rounding errors of |A| |x| (31 columns, entries
  // below 1.5: 1e-12 leaves a growth factor of ~100 over n eps |A| |x| ~ 1e-14)
  const double* a0 = SUNDenseMatrix_Data(A0);
  double worst = 0.0;
  for (sunindextype i = 0; i < kN; ++i) {
    double r = -NV_Ith_S(b, i);
    for (sunindextype j = 0; j < kN; ++j) r += a0[j * kN + i] * NV_Ith_S(x, j);
    worst = std::max(worst, std::abs(r));
  }
  CHECK(worst < 1e-12);
  // a zero column, then a NaN: a recoverable failure (CVODE retries with a new matrix)
  SUNMatCopy(A0, A);
  for (sunindextype i = 0; i < kN; ++i) a[5 * kN + i] = 0.0;
  CHECK(SUNLinSolSetup(S, A) == SUNLS_LUFACT_FAIL);
  SUNMatCopy(A0, A);
  a[3 * kN + 7] = std::numeric_limits<double>::quiet_NaN();
  CHECK(SUNLinSolSetup(S, A) == SUNLS_LUFACT_FAIL);
  N_VDestroy(b);
  N_VDestroy(x);
  SUNLinSolFree(S);
  SUNMatDestroy(A);
  SUNMatDestroy(A0);
}

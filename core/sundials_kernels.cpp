// SUNDIALS' serial vector and dense matrix arithmetic, compiled with the project's flags.
//
// Why: Debian 12's SUNDIALS 6.4.1 libraries are built without optimisation (every value goes
// through the stack; `objdump -d` of N_VWSqrSumLocal_Serial). Measured on rod-end-kinematic's
// thesis cycle at cvode_bdf 1e-6 (callgrind, 6,334 steps): N_VLinearSum took 109 M instructions
// (101,368 calls, ~690 each for 30 numbers), the weighted RMS norm 28 M, N_VScale 27 M, the
// dense copy and A = cA + I 42 M (764 of each, ~27 k per 30 x 30 matrix): about half of CVODE's
// 366 M. These are the operations CVODE calls through a vector's or matrix's table; CVODE's own
// step logic stays the library's.
//
// Each function computes what the library's computes, operation by operation and in the same
// order (N_VLinearSum's special cases included: c (x + y) for a == b rounds differently from
// a x + a y), and the two fused operations CVODE calls (linear combination, scale-add-multi)
// compute what SUNDIALS' generic fallbacks compute from those: the results are bit-identical
// to the library's.
#include "core/sundials_kernels.hpp"

#include <algorithm>
#include <cmath>
#include <new>
#include <utility>
#include <vector>

namespace rodend::detail {
namespace {

sunindextype len(N_Vector v) {
  return NV_LENGTH_S(v);
}
double* data(N_Vector v) {
  return NV_DATA_S(v);
}

/// y <- a x + y (the library's axpy, with its a = +-1 cases)
void axpy(double a, N_Vector x, N_Vector y) {
  const double* xd = data(x);
  double* yd = data(y);
  const sunindextype n = len(x);
  if (a == 1.0) {
    for (sunindextype i = 0; i < n; ++i) yd[i] += xd[i];
  } else if (a == -1.0) {
    for (sunindextype i = 0; i < n; ++i) yd[i] -= xd[i];
  } else {
    for (sunindextype i = 0; i < n; ++i) yd[i] += a * xd[i];
  }
}

/// z = f(x_i, y_i) element by element (x, y, z may be the same vector)
template <class F>
void zip(N_Vector x, N_Vector y, N_Vector z, F f) {
  const double *xd = data(x), *yd = data(y);
  double* zd = data(z);
  const sunindextype n = len(x);
  for (sunindextype i = 0; i < n; ++i) zd[i] = f(xd[i], yd[i]);
}

/// z = f(x_i) element by element
template <class F>
void map(N_Vector x, N_Vector z, F f) {
  const double* xd = data(x);
  double* zd = data(z);
  const sunindextype n = len(x);
  for (sunindextype i = 0; i < n; ++i) zd[i] = f(xd[i]);
}

/// z = a x + b y, by the library's case analysis
void linear_sum(double a, N_Vector x, double b, N_Vector y, N_Vector z) {
  if (b == 1.0 && z == y) return axpy(a, x, y);
  if (a == 1.0 && z == x) return axpy(b, y, x);
  if (a == 1.0 && b == 1.0) return zip(x, y, z, [](double u, double v) { return u + v; });
  if (a == 1.0 && b == -1.0) return zip(x, y, z, [](double u, double v) { return u - v; });
  if (a == -1.0 && b == 1.0) return zip(y, x, z, [](double u, double v) { return u - v; });
  // one coefficient 1: c v1 + v2
  if (a == 1.0) return zip(y, x, z, [b](double u, double v) { return b * u + v; });
  if (b == 1.0) return zip(x, y, z, [a](double u, double v) { return a * u + v; });
  // one coefficient -1: c v1 - v2
  if (a == -1.0) return zip(y, x, z, [b](double u, double v) { return b * u - v; });
  if (b == -1.0) return zip(x, y, z, [a](double u, double v) { return a * u - v; });
  if (a == b) return zip(x, y, z, [a](double u, double v) { return a * (u + v); });
  if (a == -b) return zip(x, y, z, [a](double u, double v) { return a * (u - v); });
  zip(x, y, z, [a, b](double u, double v) { return a * u + b * v; });
}

void scale(double c, N_Vector x, N_Vector z) {
  if (z == x) return map(x, x, [c](double u) { return u * c; });
  if (c == 1.0) return map(x, z, [](double u) { return u; });
  if (c == -1.0) return map(x, z, [](double u) { return -u; });
  map(x, z, [c](double u) { return c * u; });
}

void constant(double c, N_Vector z) {
  std::fill(data(z), data(z) + len(z), c);
}
void abs(N_Vector x, N_Vector z) {
  map(x, z, [](double u) { return std::abs(u); });
}
void inv(N_Vector x, N_Vector z) {
  map(x, z, [](double u) { return 1.0 / u; });
}
void add_const(N_Vector x, double b, N_Vector z) {
  map(x, z, [b](double u) { return u + b; });
}
void prod(N_Vector x, N_Vector y, N_Vector z) {
  zip(x, y, z, [](double u, double v) { return u * v; });
}
void div(N_Vector x, N_Vector y, N_Vector z) {
  zip(x, y, z, [](double u, double v) { return u / v; });
}

/// sum of (x_i w_i)^2, in index order
double wsqr_sum(N_Vector x, N_Vector w) {
  const double *xd = data(x), *wd = data(w);
  double sum = 0.0;
  for (sunindextype i = 0; i < len(x); ++i) {
    const double p = xd[i] * wd[i];
    sum += p * p;
  }
  return sum;
}

double wrms_norm(N_Vector x, N_Vector w) {
  const double m = wsqr_sum(x, w) / static_cast<double>(len(x));
  return m <= 0.0 ? 0.0 : std::sqrt(m);
}

/// z = c_0 X_0 + c_1 X_1 + ...: what SUNDIALS' generic fallback computes (z = c_0 X_0, then
/// z += c_i X_i vector by vector, so an X_i that is z reads the partial sum), without its
/// unoptimised dispatch per term. CVODE's prediction, interpolation and corrections use it.
int linear_combination(int nvec, double* c, N_Vector* X, N_Vector z) {
  scale(c[0], X[0], z);
  for (int i = 1; i < nvec; ++i) axpy(c[i], X[i], z);
  return 0;
}

/// Z_i = a_i x + Y_i, i = 0, 1, ..., one after the other (a Z_i that is x changes the x of
/// the next ones, as in SUNDIALS' fallback)
int scale_add_multi(int nvec, double* a, N_Vector x, N_Vector* Y, N_Vector* Z) {
  for (int i = 0; i < nvec; ++i) linear_sum(a[i], x, 1.0, Y[i], Z[i]);
  return 0;
}

int matrix_zero(SUNMatrix A) {
  std::fill(SM_DATA_D(A), SM_DATA_D(A) + SM_LDATA_D(A), 0.0);
  return SUNMAT_SUCCESS;
}

int matrix_copy(SUNMatrix A, SUNMatrix B) {
  if (SUNMatGetID(B) != SUNMATRIX_DENSE || SM_ROWS_D(A) != SM_ROWS_D(B) ||
      SM_COLUMNS_D(A) != SM_COLUMNS_D(B))
    return SUNMAT_ILL_INPUT;
  std::copy(SM_DATA_D(A), SM_DATA_D(A) + SM_LDATA_D(A), SM_DATA_D(B));  // both column-major
  return SUNMAT_SUCCESS;
}

/// A = c A + I
int matrix_scale_add_identity(double c, SUNMatrix A) {
  const sunindextype rows = SM_ROWS_D(A), cols = SM_COLUMNS_D(A);
  double* a = SM_DATA_D(A);
  for (sunindextype j = 0; j < cols; ++j) {
    double* col = a + j * rows;
    for (sunindextype i = 0; i < rows; ++i) col[i] *= c;
    if (j < rows) col[j] += 1.0;
  }
  return SUNMAT_SUCCESS;
}

SUNMatrix matrix_clone(SUNMatrix A) {
  SUNMatrix B = SUNDenseMatrix(SM_ROWS_D(A), SM_COLUMNS_D(A), A->sunctx);
  if (B) use_fast_ops(B);
  return B;
}

/// LU with partial pivoting of the column-major n x n matrix a, in place (L unit lower, U upper),
/// right-looking: each column's multipliers, then a rank-one update of the columns to its
/// right, their inner loops down contiguous columns. piv[k]: the row swapped with row k.
/// Returns false at a zero or non-finite pivot.
bool lu_factor(double* a, sunindextype n, std::vector<sunindextype>& piv) {
  piv.resize(static_cast<std::size_t>(n));
  for (sunindextype k = 0; k < n; ++k) {
    double* ck = a + k * n;
    sunindextype p = k;
    double best = std::abs(ck[k]);
    for (sunindextype i = k + 1; i < n; ++i)
      if (std::abs(ck[i]) > best) best = std::abs(ck[p = i]);
    if (!(best > 0.0) || !std::isfinite(best)) return false;
    piv[static_cast<std::size_t>(k)] = p;
    if (p != k)
      for (sunindextype j = 0; j < n; ++j) std::swap(a[j * n + k], a[j * n + p]);
    const double pivot = ck[k];
    for (sunindextype i = k + 1; i < n; ++i) ck[i] /= pivot;
    for (sunindextype j = k + 1; j < n; ++j) {
      double* cj = a + j * n;
      const double u = cj[k];
      if (u != 0.0)
        for (sunindextype i = k + 1; i < n; ++i) cj[i] -= ck[i] * u;
    }
  }
  return true;
}

/// lu_factor's factors with their zeros left out, column by column: the Newton matrix of a
/// mechanism is sparse (rod-end-kinematic: about 40 % of its 30 x 30 factors are non-zero), and
/// CVODE solves with one factorisation ~10 times. The solve does what a dense one does in the
/// same order, less the products with zero: its results are the same.
struct SparseFactors {
  std::vector<sunindextype> piv;   ///< lu_factor's row swaps
  std::vector<double> diag;        ///< U's diagonal
  std::vector<double> val;         ///< L's, then U's off-diagonal non-zeros, by column
  std::vector<sunindextype> row;   ///< their rows
  std::vector<std::size_t> start;  ///< column k of L: [start[k], start[k+1]), of U: from n + k

  void compress(const double* a, sunindextype n) {
    const auto un = static_cast<std::size_t>(n);
    diag.resize(un);
    start.resize(2 * un + 1);
    val.resize(un * un);  // room for all: no reallocation, no push_back
    row.resize(un * un);
    std::size_t m = 0;
    for (std::size_t part = 0; part < 2; ++part)  // L (below the diagonal), then U (above)
      for (sunindextype k = 0; k < n; ++k) {
        start[part * un + static_cast<std::size_t>(k)] = m;
        const double* ck = a + k * n;
        const sunindextype end = part == 0 ? n : k;
        for (sunindextype i = part == 0 ? k + 1 : 0; i < end; ++i) {
          val[m] = ck[i];
          row[m] = i;
          m += ck[i] != 0.0;  // a zero is overwritten by the next entry
        }
        diag[static_cast<std::size_t>(k)] = ck[k];
      }
    start[2 * un] = m;
  }

  /// x = A^-1 x: P, then L y = P b forwards, U x = y backwards
  void solve(double* x) const {
    const auto n = diag.size();
    for (std::size_t k = 0; k < n; ++k) std::swap(x[k], x[piv[k]]);
    for (std::size_t k = 0; k < n; ++k) {
      const double xk = x[k];
      for (std::size_t e = start[k]; e < start[k + 1]; ++e) x[row[e]] -= val[e] * xk;
    }
    for (std::size_t k = n; k-- > 0;) {
      x[k] /= diag[k];
      const double xk = x[k];
      for (std::size_t e = start[n + k]; e < start[n + k + 1]; ++e) x[row[e]] -= val[e] * xk;
    }
  }
};

/// CVODE's direct linear solver on its dense matrix (make_dense_lu).
///
/// Measured on rod-end-kinematic's thesis cycle at cvode_bdf 1e-6 (callgrind, 30 states, 764
/// factorisations, 7,932 solves): Eigen's PartialPivLU on a dynamic matrix (blocked above 16
/// columns, a matrix-matrix product per block) took 67.7 k instructions per factorisation and
/// 5.1 k per solve; these loops take 25 k + 11 k to compress the factors, and 3.3 k per solve
/// (5.7 k with the zeros). (Before Eigen's, SUNDIALS' own SUNLinSol_Dense, unoptimised in
/// Debian's build, took 186 M of a 589 M run at 1e-5.) Dense, not band or KLU: the Jacobian of
/// the rod-end scenes couples every body state with every other through the contact and the
/// springs, and a sparse factorisation would need a CSC Jacobian of the scene, which CVODE
/// cannot difference itself. Leaving the audit states' unit columns out of the factorisation
/// (A = [M 0; X I]) saved nothing: the update already skips their zero rows of U.
struct DenseLu {
  SparseFactors f;
  static DenseLu* of(SUNLinearSolver S) { return static_cast<DenseLu*>(S->content); }
  static SUNLinearSolver_Type type(SUNLinearSolver) { return SUNLINEARSOLVER_DIRECT; }
  static SUNLinearSolver_ID id(SUNLinearSolver) { return SUNLINEARSOLVER_CUSTOM; }
  static int setup(SUNLinearSolver S, SUNMatrix A) {
    // failure: CVODE treats a positive return as recoverable (shorter step, new matrix)
    SparseFactors& f = of(S)->f;
    if (!lu_factor(SM_DATA_D(A), SM_ROWS_D(A), f.piv)) return SUNLS_LUFACT_FAIL;
    f.compress(SM_DATA_D(A), SM_ROWS_D(A));
    return SUNLS_SUCCESS;
  }
  static int solve(SUNLinearSolver S, SUNMatrix, N_Vector x, N_Vector b, double) {
    if (x != b) std::copy(data(b), data(b) + len(b), data(x));
    of(S)->f.solve(data(x));
    return SUNLS_SUCCESS;
  }
  static int free(SUNLinearSolver S) {
    if (!S) return 0;
    delete of(S);
    S->content = nullptr;
    SUNLinSolFreeEmpty(S);
    return 0;
  }
};

}  // namespace

void use_fast_ops(N_Vector v) {
  N_Vector_Ops o = v->ops;
  o->nvlinearsum = &linear_sum;
  o->nvscale = &scale;
  o->nvconst = &constant;
  o->nvabs = &abs;
  o->nvinv = &inv;
  o->nvaddconst = &add_const;
  o->nvprod = &prod;
  o->nvdiv = &div;
  o->nvwrmsnorm = &wrms_norm;
  o->nvwsqrsumlocal = &wsqr_sum;
  o->nvlinearcombination = &linear_combination;
  o->nvscaleaddmulti = &scale_add_multi;
}

void use_fast_ops(SUNMatrix A) {
  SUNMatrix_Ops o = A->ops;
  o->zero = &matrix_zero;
  o->copy = &matrix_copy;
  o->scaleaddi = &matrix_scale_add_identity;
  o->clone = &matrix_clone;
}

SUNLinearSolver make_dense_lu(SUNContext ctx) {
  SUNLinearSolver S = SUNLinSolNewEmpty(ctx);
  if (!S) return nullptr;
  S->content = new (std::nothrow) DenseLu;
  if (!S->content) {
    SUNLinSolFreeEmpty(S);
    return nullptr;
  }
  S->ops->gettype = &DenseLu::type;
  S->ops->getid = &DenseLu::id;
  S->ops->setup = &DenseLu::setup;
  S->ops->solve = &DenseLu::solve;
  S->ops->free = &DenseLu::free;
  return S;
}

}  // namespace rodend::detail

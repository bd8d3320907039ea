// Internal to core (steppers_cvode.cpp): SUNDIALS' serial vector and dense matrix operations
// compiled with the project's flags, put in place of the library's in a vector's or a matrix's
// operation table, and CVODE's dense direct linear solver.
#pragma once

#include <nvector/nvector_serial.h>
#include <sundials/sundials_linearsolver.h>
#include <sunmatrix/sunmatrix_dense.h>

namespace rodend::detail {

/// Replaces the arithmetic operations of serial vector v (linear sum, scale, constant, absolute
/// value, inverse, add constant, weighted RMS norm, product, division, and the fused linear
/// combination and scale-add-multi) by ours. Clones made
/// afterwards (N_VClone: CVODE's own vectors) copy the table, so this is done once, on the
/// template vector, before CVodeInit. Each computes exactly what the library's does, operation
/// by operation (the same special cases of N_VLinearSum, the same order of the sum of squares,
/// the fused ones as SUNDIALS' fallbacks): the results are bit-identical.
void use_fast_ops(N_Vector v);

/// Replaces the zero, copy, A = cA + I and clone operations of dense matrix A by ours; its clones
/// (CVODE's saved Jacobian) get the same table. Bit-identical, as use_fast_ops.
void use_fast_ops(SUNMatrix A);

/// A direct linear solver on a dense matrix: LU with partial pivoting, factorised in place (as
/// SUNDIALS' SUNLinSol_Dense). A zero or non-finite pivot is a recoverable failure (CVODE tries
/// a shorter step with a new matrix). Null if it cannot be allocated.
SUNLinearSolver make_dense_lu(SUNContext ctx);

}  // namespace rodend::detail

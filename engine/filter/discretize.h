// Exact discretisation of a continuous linear model ẋ = A x + B u + G w, E[w w^T] = Qc δ(t−s):
// the matrix exponential for F and the input matrix, and Van Loan's method for the process noise.
#pragma once

#include "core/expected.h"
#include "core/types.h"

namespace kfw {

// e^{M}, scaling and squaring with a Taylor series to double precision (small, dense M).
MatX expm(const MatX& M);

struct Discretized {
  MatX F;      // e^{A T}
  MatX Gamma;  // ∫_0^T e^{A s} ds B (zero-order-hold input); empty when B is empty
  MatX Q;      // ∫_0^T e^{A s} G Qc G^T e^{A^T s} ds
};

// Van Loan (1978): expm([[-A, G Qc G^T], [0, A^T]] T) = [[·, F^{-1} Q], [0, F^T]], so
// Q = F · (upper-right block). The input matrix from expm([[A, B], [0, 0]] T). Errors name the
// argument whose size does not fit or a non-finite / non-positive T.
Expected<Discretized> van_loan(const MatX& A, const MatX& B, const MatX& G, const MatX& Qc,
                               double T_s);

}  // namespace kfw

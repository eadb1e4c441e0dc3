// The fixed C of an exported filter (c_runtime.h). Each piece follows the engine's function it
// names, operation for operation where the order of rounding matters.
#include "codegen/c_runtime.h"

#include <cctype>

#include <map>
#include <vector>

namespace kfw::codegen {

namespace {

struct Piece {
  const char* name;
  std::vector<const char*> needs;
  const char* text;
};

// In emission order: a piece comes after those it calls.
const std::vector<Piece>& pieces() {
  static const std::vector<Piece> p = {
      {"kfw_sq", {}, R"C(static real kfw_sq(real v) { return v * v; }
)C"},
      {"kfw_cube", {}, R"C(static real kfw_cube(real v) { return v * v * v; }
)C"},
      {"kfw_sinc", {}, R"C(/* sin(v)/v, 1 at 0 (model/expression.cpp). */
static real kfw_sinc(real v) { return v == LIT(0.0) ? LIT(1.0) : SIN(v) / v; }
)C"},
      {"kfw_dsinc",
       {},
       R"C(/* (cos v - sinc v)/v, its series below |v| = 0.1 (model/expression.cpp). */
static real kfw_dsinc(real v) {
  if (FABS(v) < LIT(0.1)) {
    const real v2 = v * v;
    return v * (-LIT(1.0) / LIT(3.0) +
                v2 * (LIT(1.0) / LIT(30.0) +
                      v2 * (-LIT(1.0) / LIT(840.0) +
                            v2 * (LIT(1.0) / LIT(45360.0) +
                                  v2 * (-LIT(1.0) / LIT(3991680.0) + v2 / LIT(518918400.0))))));
  }
  return (COS(v) - SIN(v) / v) / v;
}
)C"},
      {"kfw_heaviside", {}, R"C(static real kfw_heaviside(real v) {
  return v >= LIT(0.0) ? LIT(1.0) : (v < LIT(0.0) ? LIT(0.0) : v);
}
)C"},
      {"kfw_sign", {}, R"C(static real kfw_sign(real v) {
  return v > LIT(0.0) ? LIT(1.0) : (v < LIT(0.0) ? -LIT(1.0) : LIT(0.0));
}
)C"},
      {"kfw_step", {}, R"C(static real kfw_step(real v) {
  return v > LIT(0.0) ? LIT(1.0) : (v < LIT(0.0) ? LIT(0.0) : LIT(0.5));
}
)C"},
      {"wrap_angle",
       {},
       R"C(/* An angle wrapped to (-pi, pi] (kind 1, rad) or (-180, 180] (kind 2, deg); kind 0: unchanged. */
static real wrap_angle(real v, int kind) {
  real period, r;
  if (kind == 0) return v;
  period = kind == 1 ? LIT(6.283185307179586) : LIT(360.0);
  r = REMAINDER(v, period);
  if (r <= -LIT(0.5) * period) r += period;
  return r;
}
)C"},
      {"diverged", {}, R"C(/* The state or a variance not finite: the engine stops its run there. */
static int diverged(const real x[NX], real P[NX][NX]) {
  int i;
  for (i = 0; i < NX; ++i) {
    if (!isfinite(x[i]) || !isfinite(P[i][i])) return 1;
  }
  return 0;
}
)C"},
      {"predict_cov", {}, R"C(/* P = F P F' + Q (filter/kalman_filter.h, predict_covariance). */
static void predict_cov(real P[NX][NX], real F[NX][NX], real Q[NX][NX]) {
  real FP[NX][NX];
  int i, j, k;
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) {
      real v = LIT(0.0);
      for (k = 0; k < NX; ++k) v += F[i][k] * P[k][j];
      FP[i][j] = v;
    }
  }
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) {
      real v = LIT(0.0);
      for (k = 0; k < NX; ++k) v += FP[i][k] * F[j][k];
      P[i][j] = v + Q[i][j];
    }
  }
}
)C"},
      {"update_scalar",
       {},
       R"C(/* A scalar measurement, y = z - zhat (wrapped): S = h P h' + r, K = P h'/S, and the Joseph form
   P - K C' - C K' + S K K' on the upper triangle, mirrored (filter/measurement_update.h).
   1: applied (*logdet = log S when logdet is given); 0: gated (NIS above `gate`); -1: S not
   positive or not finite. */
static int update_scalar(real x[NX], real P[NX][NX], const real h[NX], real r, real y, real gate,
                         real *nis, real *logdet) {
  real C[NX], K[NX], S = LIT(0.0), v;
  int i, j;
  for (i = 0; i < NX; ++i) {
    real c = LIT(0.0);
    for (j = 0; j < NX; ++j) c += P[i][j] * h[j];
    C[i] = c;
  }
  for (i = 0; i < NX; ++i) S += h[i] * C[i];
  S += r;
  if (nis) *nis = NAN;
  if (!(S > LIT(0.0)) || !isfinite(S)) return -1;
  v = y * y / S;
  if (nis) *nis = v;
  if (gate > LIT(0.0) && v > gate) return 0;
  if (logdet) *logdet = LOG(S);
  for (i = 0; i < NX; ++i) {
    K[i] = C[i] / S;
    x[i] += K[i] * y;
  }
  for (j = 0; j < NX; ++j) {
    for (i = 0; i <= j; ++i) {
      real p = P[i][j] - K[i] * C[j];
      p -= C[i] * K[j];
      p += (S * K[i]) * K[j];
      P[i][j] = p;
      P[j][i] = p;
    }
  }
  return 1;
}
)C"},
      {"chol",
       {},
       R"C(/* The lower Cholesky factor L of the m x m matrix A (row stride ld); 0 when A is not positive
   definite (filter/ukf.h, cholesky_lower). */
static int chol(int m, int ld, const real *A, real *L) {
  int i, j, k;
  for (i = 0; i < m * ld; ++i) L[i] = LIT(0.0);
  for (j = 0; j < m; ++j) {
    real d = A[j * ld + j], ljj;
    for (k = 0; k < j; ++k) d -= L[j * ld + k] * L[j * ld + k];
    if (!(d > LIT(0.0))) return 0;
    ljj = SQRT(d);
    L[j * ld + j] = ljj;
    for (i = j + 1; i < m; ++i) {
      real v = A[i * ld + j];
      for (k = 0; k < j; ++k) v -= L[i * ld + k] * L[j * ld + k];
      L[i * ld + j] = v / ljj;
    }
  }
  return 1;
}
)C"},
      {"update_vec",
       {"chol"},
       R"C(/* A measurement of m components, y = z - zhat (angles wrapped), S and C = P H' (or the sigma
   points' P_xz): S factored, NIS = y' S^-1 y, K = C S^-1, x += K y, and P in Joseph form
   (I - K H) P (I - K H)' + K R K' when H is given, else P - K S K'; then symmetrised
   (filter/measurement_update.h). 1: applied (*logdet = log det S when logdet is given); 0:
   gated; -1: S not positive definite. */
static int update_vec(real x[NX], real P[NX][NX], int m, const real y[MX], real S[MX][MX],
                      real C[NX][MX], real H[MX][NX], real R[MX][MX], real gate, real *nis,
                      real *logdet) {
  real L[MX][MX], w[MX], K[NX][MX], T[NX][NX], A[NX][NX], v = LIT(0.0);
  int i, j, a, b;
  if (nis) *nis = NAN;
  for (a = 0; a < m; ++a) {
    for (b = 0; b < m; ++b) {
      if (!isfinite(S[a][b])) return -1;
    }
  }
  if (!chol(m, MX, &S[0][0], &L[0][0])) return -1;
  for (a = 0; a < m; ++a) { /* w = L^-1 y */
    real s = y[a];
    for (b = 0; b < a; ++b) s -= L[a][b] * w[b];
    w[a] = s / L[a][a];
    v += w[a] * w[a];
  }
  if (nis) *nis = v;
  if (gate > LIT(0.0) && v > gate) return 0;
  if (logdet) {
    real ld = LIT(0.0);
    for (a = 0; a < m; ++a) ld += LIT(2.0) * LOG(L[a][a]);
    *logdet = ld;
  }
  for (i = 0; i < NX; ++i) { /* K(i, :) solves S k = C(i, :)' */
    real s[MX];
    for (a = 0; a < m; ++a) {
      real t = C[i][a];
      for (b = 0; b < a; ++b) t -= L[a][b] * s[b];
      s[a] = t / L[a][a];
    }
    for (a = m - 1; a >= 0; --a) {
      real t = s[a];
      for (b = a + 1; b < m; ++b) t -= L[b][a] * K[i][b];
      K[i][a] = t / L[a][a];
    }
  }
  for (i = 0; i < NX; ++i) {
    real s = LIT(0.0);
    for (a = 0; a < m; ++a) s += K[i][a] * y[a];
    x[i] += s;
  }
  if (H) {
    real IKH[NX][NX];
    for (i = 0; i < NX; ++i) {
      for (j = 0; j < NX; ++j) {
        real s = i == j ? LIT(1.0) : LIT(0.0);
        for (a = 0; a < m; ++a) s -= K[i][a] * H[a][j];
        IKH[i][j] = s;
      }
    }
    for (i = 0; i < NX; ++i) {
      for (j = 0; j < NX; ++j) {
        real s = LIT(0.0);
        for (a = 0; a < NX; ++a) s += IKH[i][a] * P[a][j];
        T[i][j] = s;
      }
    }
    for (i = 0; i < NX; ++i) {
      for (j = 0; j < NX; ++j) {
        real s = LIT(0.0);
        for (a = 0; a < NX; ++a) s += T[i][a] * IKH[j][a];
        A[i][j] = s;
      }
    }
    for (i = 0; i < NX; ++i) {
      for (j = 0; j < NX; ++j) {
        real s = LIT(0.0);
        for (a = 0; a < m; ++a) {
          real kr = LIT(0.0);
          for (b = 0; b < m; ++b) kr += K[i][b] * R[b][a];
          s += kr * K[j][a];
        }
        A[i][j] += s;
      }
    }
  } else {
    for (i = 0; i < NX; ++i) {
      for (j = 0; j < NX; ++j) {
        real s = LIT(0.0);
        for (a = 0; a < m; ++a) {
          real ks = LIT(0.0);
          for (b = 0; b < m; ++b) ks += K[i][b] * S[b][a];
          s += ks * K[j][a];
        }
        A[i][j] = P[i][j] - s;
      }
    }
  }
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) P[i][j] = LIT(0.5) * (A[i][j] + A[j][i]);
  }
  return 1;
}
)C"},
      {"expm",
       {},
       R"C(/* e^M of the d x d matrix M: scaling and squaring with 18 Taylor terms (filter/discretize.cpp). */
static void expm(int d, real M[EM][EM], real E[EM][EM]) {
  real X[EM][EM], T[EM][EM], W[EM][EM], norm = LIT(0.0), scale;
  int i, j, k, q, s = 0;
  for (j = 0; j < d; ++j) {
    real c = LIT(0.0);
    for (i = 0; i < d; ++i) c += FABS(M[i][j]);
    if (c > norm) norm = c;
  }
  if (norm > LIT(0.5)) s = (int)CEIL(LOG2(norm / LIT(0.5)));
  scale = LDEXP(LIT(1.0), s);
  for (i = 0; i < d; ++i) {
    for (j = 0; j < d; ++j) {
      X[i][j] = M[i][j] / scale;
      T[i][j] = E[i][j] = i == j ? LIT(1.0) : LIT(0.0);
    }
  }
  for (k = 1; k <= 18; ++k) {
    for (i = 0; i < d; ++i) {
      for (j = 0; j < d; ++j) {
        real v = LIT(0.0);
        for (q = 0; q < d; ++q) v += T[i][q] * X[q][j];
        W[i][j] = v;
      }
    }
    for (i = 0; i < d; ++i) {
      for (j = 0; j < d; ++j) {
        T[i][j] = W[i][j] / (real)k;
        E[i][j] += T[i][j];
      }
    }
  }
  for (k = 0; k < s; ++k) {
    for (i = 0; i < d; ++i) {
      for (j = 0; j < d; ++j) {
        real v = LIT(0.0);
        for (q = 0; q < d; ++q) v += E[i][q] * E[q][j];
        W[i][j] = v;
      }
    }
    for (i = 0; i < d; ++i) {
      for (j = 0; j < d; ++j) E[i][j] = W[i][j];
    }
  }
}
)C"},
      {"van_loan",
       {"expm"},
       R"C(/* Van Loan (1978): e^([-A, W; 0, A'] dt) = [., F^-1 Q; 0, F'] with W = G Qc G', so F = e^(A dt)
   and Q = F (upper-right block), symmetrised (filter/discretize.cpp). */
static void van_loan(real A[NX][NX], real W[NX][NX], real dt, real F[NX][NX], real Q[NX][NX]) {
  real C[EM][EM], E[EM][EM];
  int i, j, k;
  for (i = 0; i < 2 * NX; ++i) {
    for (j = 0; j < 2 * NX; ++j) C[i][j] = LIT(0.0);
  }
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) {
      C[i][j] = -A[i][j] * dt;
      C[i][NX + j] = W[i][j] * dt;
      C[NX + i][NX + j] = A[j][i] * dt;
    }
  }
  expm(2 * NX, C, E);
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) F[i][j] = E[NX + j][NX + i];
  }
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) {
      real v = LIT(0.0);
      for (k = 0; k < NX; ++k) v += F[i][k] * E[k][NX + j];
      C[i][j] = v;
    }
  }
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) Q[i][j] = LIT(0.5) * (C[i][j] + C[j][i]);
  }
}
)C"},
      {"rk4",
       {},
       R"C(/* The classical RK4 of xdot = f(x, u, t) over dt in `steps` equal sub-steps from x0 at t0, and
   (F given) the exact Jacobian of that step map, the chain rule through the four stages of every
   sub-step with A = df/dx (model/model_continuous.cpp). */
static void rk4(void (*f)(const void *, const real *, const real *, real, real *),
                void (*jac)(const void *, const real *, const real *, real, real (*)[NX]),
                const void *ctx, const real x0[NX], const real *u, real t0, real dt, int steps,
                real fx[NX], real F[NX][NX]) {
  const real h = dt / (real)steps;
  const real c[4] = {LIT(0.0), LIT(0.5), LIT(0.5), LIT(1.0)};
  real x[NX], xs[NX], k[4][NX], A[NX][NX], D[4][NX][NX], T[NX][NX];
  int i, j, q, s, stage;
  for (i = 0; i < NX; ++i) {
    x[i] = x0[i];
    if (F) {
      for (j = 0; j < NX; ++j) F[i][j] = i == j ? LIT(1.0) : LIT(0.0);
    }
  }
  for (s = 0; s < steps; ++s) {
    const real ts = t0 + (real)s * h;
    for (stage = 0; stage < 4; ++stage) {
      /* the stage at x + c h k_prev, ts + c h; its D = A (I + c h D_prev) */
      const real tc = stage ? ts + c[stage] * h : ts;
      for (i = 0; i < NX; ++i) xs[i] = stage ? x[i] + c[stage] * h * k[stage - 1][i] : x[i];
      f(ctx, xs, u, tc, k[stage]);
      if (!F) continue;
      jac(ctx, xs, u, tc, A);
      for (i = 0; i < NX; ++i) {
        for (j = 0; j < NX; ++j) {
          real v = LIT(0.0);
          if (!stage) {
            D[0][i][j] = A[i][j];
            continue;
          }
          for (q = 0; q < NX; ++q)
            v += A[i][q] * ((q == j ? LIT(1.0) : LIT(0.0)) + c[stage] * h * D[stage - 1][q][j]);
          D[stage][i][j] = v;
        }
      }
    }
    for (i = 0; i < NX; ++i)
      x[i] += (h / LIT(6.0)) * (k[0][i] + LIT(2.0) * k[1][i] + LIT(2.0) * k[2][i] + k[3][i]);
    if (!F) continue;
    for (i = 0; i < NX; ++i) {
      for (j = 0; j < NX; ++j) {
        real v = LIT(0.0);
        for (q = 0; q < NX; ++q) {
          const real m = (i == q ? LIT(1.0) : LIT(0.0)) +
                         (h / LIT(6.0)) * (D[0][i][q] + LIT(2.0) * D[1][i][q] +
                                           LIT(2.0) * D[2][i][q] + D[3][i][q]);
          v += m * F[q][j];
        }
        T[i][j] = v;
      }
    }
    for (i = 0; i < NX; ++i) {
      for (j = 0; j < NX; ++j) F[i][j] = T[i][j];
    }
  }
  for (i = 0; i < NX; ++i) fx[i] = x[i];
}
)C"},
      {"van_loan_input",
       {"expm"},
       R"C(/* The zero-order-hold input matrix: the upper-right block of e^([A, B; 0, 0] dt). */
static void van_loan_input(real A[NX][NX], real B[NX][NU], real dt, real G[NX][NU]) {
  real C[EM][EM], E[EM][EM];
  int i, j;
  for (i = 0; i < NX + NU; ++i) {
    for (j = 0; j < NX + NU; ++j) C[i][j] = LIT(0.0);
  }
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) C[i][j] = A[i][j] * dt;
    for (j = 0; j < NU; ++j) C[i][NX + j] = B[i][j] * dt;
  }
  expm(NX + NU, C, E);
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NU; ++j) G[i][j] = E[i][NX + j];
  }
}
)C"},
      {"sym_sqrt",
       {},
       R"C(/* The symmetric square root V sqrt(L) V' of a positive semi-definite A by Jacobi rotations; 0 when
   an eigenvalue is below -1e-9 of the largest (filter/ukf.cpp, symmetric_sqrt). */
static int sym_sqrt(real A[NX][NX], real L[NX][NX]) {
  real D[NX][NX], V[NX][NX], big = LIT(0.0);
  int i, j, k, p, q, sweep;
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) {
      D[i][j] = A[i][j];
      V[i][j] = i == j ? LIT(1.0) : LIT(0.0);
    }
  }
  for (sweep = 0; sweep < 100; ++sweep) {
    real off = LIT(0.0);
    for (p = 0; p < NX; ++p) {
      for (q = p + 1; q < NX; ++q) off += D[p][q] * D[p][q];
    }
    if (!(off > LIT(0.0))) break;
    for (p = 0; p < NX; ++p) {
      for (q = p + 1; q < NX; ++q) {
        real theta, tt, c, s;
        if (D[p][q] == LIT(0.0)) continue;
        theta = (D[q][q] - D[p][p]) / (LIT(2.0) * D[p][q]);
        tt = (theta >= LIT(0.0) ? LIT(1.0) : -LIT(1.0)) / (FABS(theta) + SQRT(theta * theta + LIT(1.0)));
        c = LIT(1.0) / SQRT(tt * tt + LIT(1.0));
        s = tt * c;
        for (k = 0; k < NX; ++k) {
          const real dkp = D[k][p], dkq = D[k][q];
          D[k][p] = c * dkp - s * dkq;
          D[k][q] = s * dkp + c * dkq;
        }
        for (k = 0; k < NX; ++k) {
          const real dpk = D[p][k], dqk = D[q][k];
          D[p][k] = c * dpk - s * dqk;
          D[q][k] = s * dpk + c * dqk;
        }
        for (k = 0; k < NX; ++k) {
          const real vkp = V[k][p], vkq = V[k][q];
          V[k][p] = c * vkp - s * vkq;
          V[k][q] = s * vkp + c * vkq;
        }
      }
    }
  }
  for (i = 0; i < NX; ++i) {
    if (FABS(D[i][i]) > big) big = FABS(D[i][i]);
  }
  for (i = 0; i < NX; ++i) {
    if (!isfinite(D[i][i]) || D[i][i] < -LIT(1e-9) * big) return 0;
  }
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) {
      real v = LIT(0.0);
      for (k = 0; k < NX; ++k) v += V[i][k] * SQRT(D[k][k] > LIT(0.0) ? D[k][k] : LIT(0.0)) * V[j][k];
      L[i][j] = v;
    }
  }
  return 1;
}
)C"},
      {"sigma_points",
       {"chol", "sym_sqrt"},
       R"C(/* The 2n + 1 sigma points of N(x, P), columns of X: x and x +- the columns of sqrt(c P) (Cholesky;
   the symmetric root when P is singular). 0 when P lost definiteness (filter/ukf.h). */
static int sigma_points(const real x[NX], real P[NX][NX], real X[NX][NS]) {
  real A[NX][NX], L[NX][NX];
  int i, j;
  for (i = 0; i < NX; ++i) {
    for (j = 0; j < NX; ++j) A[i][j] = UKF_C * P[i][j];
  }
  if (!chol(NX, NX, &A[0][0], &L[0][0]) && !sym_sqrt(A, L)) return 0;
  for (i = 0; i < NX; ++i) {
    X[i][0] = x[i];
    for (j = 0; j < NX; ++j) {
      X[i][1 + j] = x[i] + L[i][j];
      X[i][1 + NX + j] = x[i] - L[i][j];
    }
  }
  return 1;
}

static real ukf_wm(int j) { return j == 0 ? UKF_WM0 : UKF_WI; }
static real ukf_wc(int j) { return j == 0 ? UKF_WC0 : UKF_WI; }

/* The weighted mean of one row of sigma points; an angle row as the central point plus the mean
   of the wrapped differences from it. */
static real sigma_mean(const real row[NS], int angle) {
  real s = LIT(0.0), ref;
  int j;
  if (!angle) {
    for (j = 0; j < NS; ++j) s += ukf_wm(j) * row[j];
    return s;
  }
  ref = row[0];
  for (j = 0; j < NS; ++j) s += ukf_wm(j) * wrap_angle(row[j] - ref, angle);
  return wrap_angle(ref + s, angle);
}
)C"},
  };
  return p;
}

}  // namespace

std::string c_math_macros(bool single) {
  std::string s = single ? "#define LIT(v) v##f\n" : "#define LIT(v) v\n";
  for (const char* fn :
       {"SQRT", "FABS", "SIN", "COS", "LOG", "LOG2", "EXP", "CEIL", "LDEXP", "REMAINDER"}) {
    std::string name = fn;
    for (char& c : name)
      c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    s += "#define " + std::string(fn) + " " + name + (single ? "f" : "") + "\n";
  }
  return s;
}

std::string c_runtime(std::set<std::string> wanted) {
  const auto& all = pieces();
  std::map<std::string, const Piece*> by_name;
  for (const Piece& p : all)
    by_name[p.name] = &p;
  // Close over the dependencies (a piece names only earlier ones).
  for (auto it = all.rbegin(); it != all.rend(); ++it) {
    if (!wanted.count(it->name)) continue;
    for (const char* n : it->needs)
      wanted.insert(n);
  }
  if (wanted.count("sigma_points")) wanted.insert("wrap_angle");
  std::string out;
  for (const Piece& p : all) {
    if (!wanted.count(p.name)) continue;
    out += p.text;
    out += "\n";
  }
  return out;
}

}  // namespace kfw::codegen

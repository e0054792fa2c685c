"""The Bari test-set problems of the work-precision table, for scipy and SUNDIALS.

The same problems, reference solutions and tolerance ratios as the Rust side
(`bgdsl-runtime/tests/stiff_common/mod.rs`, `stiff_work_precision.rs`): problem
descriptions and reference solutions from F. Mazzia, C. Magherini et al., *Test Set
for IVP Solvers*, release 2.4, University of Bari. Each right-hand side is written
with numpy operations only, so that it also evaluates on complex numbers: the exact
Jacobian is taken by complex-step differentiation (`jacobian`), to machine precision,
as bgdsl differentiates exactly with dual numbers.

Accuracy measures (the same in the Rust rows): with `c = atol / rtol` fixed per problem,
the correct digits are `-log10 max_i |x_i - ref_i| / (c + |ref_i|)`, and `k = max_i |x_i -
ref_i| / (atol + rtol |ref_i|)` is the factor by which the end point misses (`k > 1`) or
meets (`k <= 1`) the tolerance asked for.
"""

import numpy as np


def rober(t, y):
    r1 = 0.04 * y[0]
    r2 = 1e4 * y[1] * y[2]
    r3 = 3e7 * y[1] * y[1]
    return np.array([r2 - r1, r1 - r2 - r3, r3])


def vdpol(t, y):
    return np.array([y[1], ((1.0 - y[0] * y[0]) * y[1] - y[0]) / 1e-6])


def hires(t, y):
    r = 280.0 * y[5] * y[7]
    d7 = r - 1.81 * y[6]
    return np.array([
        -1.71 * y[0] + 0.43 * y[1] + 8.32 * y[2] + 0.0007,
        1.71 * y[0] - 8.75 * y[1],
        -10.03 * y[2] + 0.43 * y[3] + 0.035 * y[4],
        8.32 * y[1] + 1.71 * y[2] - 1.12 * y[3],
        -1.745 * y[4] + 0.43 * (y[5] + y[6]),
        -r + 0.69 * y[3] + 1.71 * y[4] - 0.43 * y[5] + 0.69 * y[6],
        d7,
        -d7,
    ])


def orego(t, y):
    return np.array([
        77.27 * (y[1] + y[0] * (1.0 - 8.375e-6 * y[0] - y[1])),
        (y[2] - (1.0 + y[0]) * y[1]) / 77.27,
        0.161 * (y[0] - y[2]),
    ])


POLLU_K = [0.35, 0.266e2, 0.123e5, 0.86e-3, 0.82e-3, 0.15e5, 0.13e-3, 0.24e5, 0.165e5,
           0.9e4, 0.22e-1, 0.12e5, 0.188e1, 0.163e5, 0.48e7, 0.35e-3, 0.175e-1, 0.1e9,
           0.444e12, 0.124e4, 0.21e1, 0.578e1, 0.474e-1, 0.178e4, 0.312e1]


def pollu(t, y):
    k = [0.0] + POLLU_K
    r = [0.0,
         k[1] * y[0], k[2] * y[1] * y[3], k[3] * y[4] * y[1], k[4] * y[6], k[5] * y[6],
         k[6] * y[6] * y[5], k[7] * y[8], k[8] * y[8] * y[5], k[9] * y[10] * y[1],
         k[10] * y[10] * y[0], k[11] * y[12], k[12] * y[9] * y[1], k[13] * y[13],
         k[14] * y[0] * y[5], k[15] * y[2], k[16] * y[3], k[17] * y[3], k[18] * y[15],
         k[19] * y[15], k[20] * y[16] * y[5], k[21] * y[18], k[22] * y[18],
         k[23] * y[0] * y[3], k[24] * y[18] * y[0], k[25] * y[19]]
    return np.array([
        -r[1] - r[10] - r[14] - r[23] - r[24] + r[2] + r[3] + r[9] + r[11] + r[12]
        + r[22] + r[25],
        -r[2] - r[3] - r[9] - r[12] + r[1] + r[21],
        -r[15] + r[1] + r[17] + r[19] + r[22],
        -r[2] - r[16] - r[17] - r[23] + r[15],
        -r[3] + r[4] + r[4] + r[6] + r[7] + r[13] + r[20],
        -r[6] - r[8] - r[14] - r[20] + r[3] + r[18] + r[18],
        -r[4] - r[5] - r[6] + r[13],
        r[4] + r[5] + r[6] + r[7],
        -r[7] - r[8],
        -r[12] + r[7] + r[9],
        -r[9] - r[10] + r[8] + r[11],
        r[9],
        -r[11] + r[10],
        -r[13] + r[12],
        r[14],
        -r[18] - r[19] + r[16],
        -r[20],
        r[20],
        -r[21] - r[22] - r[24] + r[23] + r[25],
        -r[25] + r[24],
    ])


def e5(t, y):
    a, b, c, m = 7.89e-10, 1.1e7, 1.13e3, 1e6
    decay = a * y[0]
    r_b = b * y[0] * y[2]
    r_mc = m * c * y[1] * y[2]
    r_c = c * y[3]
    d2 = decay - r_mc
    d4 = r_b - r_c
    # y3' = y2' - y4', as the test set writes it (keeps y2 - y3 - y4 = 0).
    return np.array([-decay - r_b, d2, d2 - d4, d4])


# The published y2 and y3 differ by 1.4e-3 relative although the invariant
# y2 - y3 - y4 = 0 and y4 ~ 0 (it decays at rate 1130 once y1 is gone) make them equal:
# the reference is good to about three digits in y2 and y3, and E5's correct digits
# saturate there.
E5_REF = [0.1152903278711829e-290, 0.8867655517642120e-22, 0.8854814626268838e-22, 0.0]

def arenstorf(t, y):
    mu = 0.012277471
    mu1 = 1.0 - mu
    r1 = (y[0] + mu) ** 2 + y[1] ** 2
    r2 = (y[0] - mu1) ** 2 + y[1] ** 2
    d1 = r1 * np.sqrt(r1)
    d2 = r2 * np.sqrt(r2)
    return np.array([
        y[2],
        y[3],
        y[0] + 2.0 * y[3] - mu1 * (y[0] + mu) / d1 - mu * (y[0] - mu1) / d2,
        y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - mu * y[1] / d2,
    ])


AREN_Y0 = [0.994, 0.0, 0.0, -2.00158510637908252240537862224]

# name: (f, y0, t_end, reference, c = atol / rtol)
PROBLEMS = {
    "ROBER": (rober, [1.0, 0.0, 0.0], 1e11,
              [0.2083340149701255e-7, 0.8333360770334713e-13, 0.9999999791665050], 1e-8),
    "VDPOL": (vdpol, [2.0, 0.0], 2.0, [0.1706167732170483e1, -0.8928097010247975], 1.0),
    "HIRES": (hires, [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0057], 321.8122,
              [0.7371312573325668e-3, 0.1442485726316185e-3, 0.5888729740967575e-4,
               0.1175651343283149e-2, 0.2386356198831331e-2, 0.6238968252742796e-2,
               0.2849998395185769e-2, 0.2850001604814231e-2], 1e-4),
    "OREGO": (orego, [1.0, 2.0, 3.0], 360.0,
              [0.1000814870318523e1, 0.1228178521549917e4, 0.1320554942846706e3], 1.0),
    "POLLU": (pollu, [0, 0.2, 0, 0.04, 0, 0, 0.1, 0.3, 0.01, 0, 0, 0, 0, 0, 0, 0, 0.007, 0,
                      0, 0], 60.0,
              [0.5646255480022769e-1, 0.1342484130422339, 0.4139734331099427e-8,
               0.5523140207484359e-2, 0.2018977262302196e-6, 0.1464541863493966e-6,
               0.7784249118997964e-1, 0.3245075353396018, 0.7494013383880406e-2,
               0.1622293157301561e-7, 0.1135863833257075e-7, 0.2230505975721359e-2,
               0.2087162882798630e-3, 0.1396921016840158e-4, 0.8964884856898295e-2,
               0.4352846369330103e-17, 0.6899219696263405e-2, 0.1007803037365946e-3,
               0.1772146513969984e-5, 0.5682943292316392e-4], 1.0),
    "E5": (e5, [1.76e-3, 0.0, 0.0, 0.0], 1e13, E5_REF, 1e-24),
    # Not stiff: the Arenstorf orbit (Hairer, Norsett & Wanner, Solving ODEs I, Sect.
    # II.0), periodic: the reference after one period is the initial value.
    "AREN": (arenstorf, AREN_Y0, 17.0652165601579625588917206249, AREN_Y0, 1.0),
}

# Problems for the explicit methods only (the others are for the stiff ones).
NONSTIFF = {"AREN"}


def jacobian(f):
    """The exact Jacobian of `f` by complex-step differentiation (`h = 1e-100 |y_j|`)."""

    def jac(t, y):
        y = np.asarray(y, dtype=float)
        n = len(y)
        out = np.empty((n, n))
        for j in range(n):
            h = 1e-100 * max(abs(y[j]), 1e-150)
            yc = y.astype(complex)
            yc[j] += 1j * h
            out[:, j] = np.imag(f(t, yc)) / h
        return out

    return jac


def accuracy(x, ref, rtol, atol, c):
    """(correct digits, k) of the end point `x` against `ref` (module doc)."""
    x, ref = np.asarray(x, dtype=float), np.asarray(ref, dtype=float)
    err = np.abs(x - ref)
    mixed = np.max(err / (c + np.abs(ref)))
    k = np.max(err / (atol + rtol * np.abs(ref)))
    digits = -np.log10(mixed) if mixed > 0 else float("inf")
    return digits, k

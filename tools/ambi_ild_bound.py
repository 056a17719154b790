#!/usr/bin/python3
"""The smallest worst broadband ILD error any linear order-N Ambisonic decoder can reach.

    build/release/tests/bench/ambi_cues --csv ambi_cues.csv
    /usr/bin/python3 tools/ambi_ild_bound.py --csv ambi_cues.csv [--orders 1,2,3,4,5]

Why there is a bound: on the horizontal plane the order-N spherical harmonics are the
trigonometric polynomials of degree N in azimuth, so the response of any linear order-N
decoder to a plane wave from azimuth phi, in each ear and at each frequency, is such a
polynomial, and its energy summed over frequency (what white noise measures) is a
non-negative trigonometric polynomial E(phi) of degree 2N. Conversely every non-negative
polynomial of degree 2N is |p|^2 of a degree-N one (Fejer-Riesz), so one frequency bin
can realise it. The best any decoder can do for the broadband ILD is therefore

    min over non-negative E_L, E_R of degree 2N  of  max_j |10 log10(E_L/E_R)(phi_j) - ILD_j|

and for a fixed error d the constraints ILD_j - d <= 10 log10(E_L/E_R) <= ILD_j + d are
linear in the coefficients of E_L and E_R. A bisection on d over linear feasibility
problems (SciPy's HiGHS; non-negativity on a 0.25-degree grid, E_L + E_R summed to 1)
finds the smallest d to 1e-6 dB. The targets are the "direct" rows of the CSV (the
direct rendering's ILD at each measured horizontal direction). The bound says nothing
about elevation, spectra or ITD, which a real decoder must also get right: it is a
floor, not a design.
Exit code 2 with a one-line message on bad input.
"""
import argparse

import numpy as np
from plot_common import fail, read_csv_rows

try:
    from scipy.optimize import linprog
except ImportError:  # pragma: no cover
    linprog = None


def basis(phi, degree):
    cols = [np.ones_like(phi)]
    for m in range(1, degree + 1):
        cols += [np.cos(m * phi), np.sin(m * phi)]
    return np.stack(cols, 1)


def bound(phi, ild, order):
    B, Bd = basis(phi, 2 * order), basis(np.linspace(-np.pi, np.pi, 1441), 2 * order)
    n = B.shape[1]

    def feasible(d):
        rp, rm = 10 ** ((ild + d) / 10), 10 ** ((ild - d) / 10)
        A = np.vstack([np.hstack([B, -rp[:, None] * B]), np.hstack([-B, rm[:, None] * B]),
                       np.hstack([-Bd, 0 * Bd]), np.hstack([0 * Bd, -Bd])])
        b = np.zeros(A.shape[0])
        eq = np.hstack([B.sum(0), B.sum(0)])[None, :]
        r = linprog(np.zeros(2 * n), A_ub=A, b_ub=b, A_eq=eq, b_eq=[1.0], bounds=[(None, None)] * (2 * n),
                    method="highs")
        return r.status == 0

    lo, hi = 0.0, 40.0
    while hi - lo > 1e-6:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if feasible(mid) else (mid, hi)
    return hi


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--csv", required=True, help="what ambi_cues --csv writes")
    ap.add_argument("--orders", default="1,2,3,4,5")
    a = ap.parse_args()
    if linprog is None:
        fail("needs SciPy (Debian: python3-scipy)")
    rows = [r for r in read_csv_rows(a.csv, ["series", "azimuth_deg", "ild_db"]) if r["series"] == "direct"]
    if not rows:
        fail(f"{a.csv}: no 'direct' rows")
    phi = np.deg2rad([float(r["azimuth_deg"]) for r in rows])
    ild = np.array([float(r["ild_db"]) for r in rows])
    print("| order | smallest worst ILD error any linear decoder can reach over the "
          f"{len(phi)} horizontal directions (dB) |\n|---|---|")
    for order in [int(o) for o in a.orders.split(",")]:
        print(f"| {order} | {bound(phi, ild, order):.2f} |")


if __name__ == "__main__":
    main()

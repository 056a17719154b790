#!/usr/bin/python3
"""The smallest worst broadband ILD error any linear order-N Ambisonic decoder can reach,
and what a closer ILD costs each ear's level.

    build/release/tests/bench/ambi_cues --csv ambi_cues.csv
    /usr/bin/python3 tools/ambi_ild_bound.py --csv ambi_cues.csv [--orders 1,2,3,4,5]
        [--sofa SET.sofa]

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

With --sofa (the set the CSV was measured with; python3-netcdf4), the same polynomials
give a second bound: the trade between the ILD and each ear's broadband level. The ear
energies H_L, H_R of the set's horizontal measurements (from the file: white noise's
energy is the responses' energy) are the targets; a decoder's E_L, E_R are again any
non-negative degree-2N polynomials, and

    min mean over directions and ears of |E / H - 1|

is a linear program, alone and under ILD bounds: |ILD error| <= 1.5 dB everywhere, and
|ILD error| <= the outside decoder's at each direction (its rendered error, from the CSV's
"outside MagLS (spaudiopy)" rows), strictly and with 0.05 dB of tie. (|E/H - 1| rather than
|dB|: the relative error keeps the program linear; 0.1 is about 0.4 dB.) No decoder can
meet those ILD bounds with a smaller mean level error than the program's ("none": no
decoder meets them with every ear's level above H / 10, i.e. not 10 dB quieter anywhere);
ambi_cues prints each decoder's own mean |E/H - 1| beside it.
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


def ear_energies(path, azimuths_deg):
    """Each ear's energy at the set's horizontal measurements nearest `azimuths_deg` (the
    CSV's order); receiver 0 is the left ear unless its y is negative."""
    try:
        import netCDF4
    except ImportError:  # pragma: no cover
        fail("--sofa needs python3-netcdf4")
    try:
        f = netCDF4.Dataset(path)
        ir = np.asarray(f["Data.IR"][:], dtype=float)
        pos = np.asarray(f["SourcePosition"][:], dtype=float)
        kind = getattr(f["SourcePosition"], "Type", "spherical")
        rec = np.asarray(f["ReceiverPosition"][:], dtype=float).reshape(ir.shape[1], 3, -1)[:, :, 0]
    except (OSError, KeyError, IndexError) as e:
        fail(f"{path}: not a readable SOFA HRIR set ({e})")
    if kind.lower().startswith("cartesian"):
        az = np.degrees(np.arctan2(pos[:, 1], pos[:, 0]))
        el = np.degrees(np.arctan2(pos[:, 2], np.hypot(pos[:, 0], pos[:, 1])))
    else:
        az, el = pos[:, 0], pos[:, 1]
    if rec[0, 1] < 0:
        ir = ir[:, ::-1, :]
    horizontal = np.where(np.abs(el) < 1e-3)[0]
    az_h = np.remainder(az[horizontal] + 180.0, 360.0) - 180.0
    energy = (ir[horizontal] ** 2).sum(axis=2)
    out = []
    for a in azimuths_deg:
        d = np.abs(np.remainder(az_h - a + 180.0, 360.0) - 180.0)
        if d.min() > 0.01:
            fail(f"{path}: no horizontal measurement at {a:g} deg (the CSV's directions)")
        out.append(energy[np.argmin(d)])
    return np.array(out)


def level_bound(phi, H, order, ild_bound_db=None):
    """min mean |E/H - 1| over both ears, E_L and E_R non-negative of degree 2N, with
    |10 log10(E_L/E_R) - 10 log10(H_L/H_R)| <= ild_bound_db (per direction) if given."""
    B, Bd = basis(phi, 2 * order), basis(np.linspace(-np.pi, np.pi, 1441), 2 * order)
    n, J = B.shape[1], len(phi)
    Z, ZJ, I = 0 * B, np.zeros((J, J)), np.eye(J)
    zd = np.zeros((len(Bd), 2 * J))
    # E >= 0 on a fine grid, and at the directions E >= H / 10: a decoder silent at a
    # direction (E = 0) would meet any ILD bound as 0 <= r x 0.
    rows = [np.hstack([-Bd, 0 * Bd, zd]), np.hstack([0 * Bd, -Bd, zd]),
            np.hstack([-B / H[:, :1], Z, ZJ, ZJ]), np.hstack([Z, -B / H[:, 1:], ZJ, ZJ]),
            np.hstack([B / H[:, :1], Z, -I, ZJ]), np.hstack([-B / H[:, :1], Z, -I, ZJ]),
            np.hstack([Z, B / H[:, 1:], ZJ, -I]), np.hstack([Z, -B / H[:, 1:], ZJ, -I])]
    b = [np.zeros(2 * len(Bd)), np.full(J, -0.1), np.full(J, -0.1), np.ones(J), -np.ones(J), np.ones(J), -np.ones(J)]
    if ild_bound_db is not None:
        ild = 10 * np.log10(H[:, 0] / H[:, 1])
        rp, rm = 10 ** ((ild + ild_bound_db) / 10), 10 ** ((ild - ild_bound_db) / 10)
        rows += [np.hstack([B, -rp[:, None] * B, ZJ, ZJ]), np.hstack([-B, rm[:, None] * B, ZJ, ZJ])]
        b += [np.zeros(J), np.zeros(J)]
    c = np.concatenate([np.zeros(2 * n), np.ones(2 * J) / (2 * J)])
    r = linprog(c, A_ub=np.vstack(rows), b_ub=np.concatenate(b), bounds=[(None, None)] * (2 * n) + [(0, None)] * (2 * J),
                method="highs")
    return r.fun if r.status == 0 else float("nan")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--csv", required=True, help="what ambi_cues --csv writes")
    ap.add_argument("--orders", default="1,2,3,4,5")
    ap.add_argument("--sofa", help="the set the CSV was measured with: the level-vs-ILD bound too")
    a = ap.parse_args()
    if linprog is None:
        fail("needs SciPy (Debian: python3-scipy)")
    every = read_csv_rows(a.csv, ["series", "order", "azimuth_deg", "ild_db"])
    rows = [r for r in every if r["series"] == "direct"]
    if not rows:
        fail(f"{a.csv}: no 'direct' rows")
    phi = np.deg2rad([float(r["azimuth_deg"]) for r in rows])
    ild = np.array([float(r["ild_db"]) for r in rows])
    print("| order | smallest worst ILD error any linear decoder can reach over the "
          f"{len(phi)} horizontal directions (dB) |\n|---|---|")
    orders = [int(o) for o in a.orders.split(",")]
    for order in orders:
        print(f"| {order} | {bound(phi, ild, order):.2f} |")
    if not a.sofa:
        return
    H = ear_energies(a.sofa, [float(r["azimuth_deg"]) for r in rows])
    print("\n| order | smallest mean \\|E/H - 1\\| of the two ears' broadband levels: any ILD | "
          "ILD error <= 1.5 dB | and <= the outside decoder's + 0.05 dB | and <= the outside decoder's |"
          "\n|---|---|---|---|---|")
    for order in orders:
        out = {float(r["azimuth_deg"]): float(r["ild_db"]) for r in every
               if r["series"] == "outside MagLS (spaudiopy)" and int(r["order"]) == order}
        cells = [level_bound(phi, H, order), level_bound(phi, H, order, np.full(len(phi), 1.5))]
        if len(out) == len(rows):
            o = np.abs(np.array([out[float(r["azimuth_deg"])] for r in rows]) - ild)
            cells += [level_bound(phi, H, order, np.minimum(1.5, o + 0.05)),
                      level_bound(phi, H, order, np.minimum(1.5, np.maximum(o, 1e-3)))]
        print(f"| {order} | " + " | ".join("none" if np.isnan(c) else f"{c:.3f}" for c in cells) + " |" +
              " - | - |" * (len(cells) == 2))


if __name__ == "__main__":
    main()

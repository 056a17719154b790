#!/usr/bin/python3
"""Plot the ILD and ITD of decoded Ambisonic plane waves against azimuth beside the direct rendering.

    build/release/tests/bench/ambi_cues --csv ambi_cues.csv [--outside-python PY]
    /usr/bin/python3 tools/plot_ambi_cues.py --csv ambi_cues.csv --out docs/plots/ambi_cues.png

ambi_cues.csv is what `ambi_cues --csv` writes: series, order, azimuth_deg, itd_us
(below 1.5 kHz), ild_db; series "direct" is the direct rendering. Drawn: the direct
rendering, the default decoder (MagLS, shadow-weighted) at orders 1, 3 and 5, and
the outside MagLS (spaudiopy) at order 3 when the CSV holds it; top the cues, bottom their
errors against the direct rendering. Azimuth is SOFA's: counter-clockwise from ahead,
+90 = left. Exit code 2 with a one-line message on bad input.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_common import fail, read_csv_rows, save_figure  # noqa: E402

COLUMNS = ["series", "order", "azimuth_deg", "itd_us", "ild_db"]
DEFAULT = "MagLS + joint ear fit (default)"
OUTSIDE = "outside MagLS (spaudiopy)"


def read(path):
    series = {}
    for line, r in enumerate(read_csv_rows(path, COLUMNS), start=2):
        try:
            key = (r["series"], int(r["order"]))
            vals = [float(r[c]) for c in ("azimuth_deg", "itd_us", "ild_db")]
        except ValueError:
            fail(f"{path}:{line}: a field is not a number")
        series.setdefault(key, []).append(vals)
    if ("direct", 0) not in series:
        fail(f"{path}: no 'direct' rows")
    out = {}
    for k, v in series.items():
        a = np.array(sorted(v))
        out[k] = a
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--csv", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--title", default="Ambisonic plane waves decoded binaurally (MIT KEMAR, 48 kHz)")
    a = ap.parse_args()
    s = read(a.csv)
    direct = s[("direct", 0)]
    curves = [((DEFAULT, o), f"MagLS order {o}", st) for o, st in ((1, ":"), (3, "-"), (5, "--"))]
    curves.append(((OUTSIDE, 3), "outside MagLS order 3 (spaudiopy)", "-."))
    curves = [c for c in curves if c[0] in s]
    if not curves:
        fail(f"{a.csv}: no rows of '{DEFAULT}'")
    fig, axes = plt.subplots(2, 2, figsize=(14, 8), sharex=True)
    for col, (idx, name, unit) in enumerate(((2, "ILD", "dB"), (1, "ITD below 1.5 kHz", "us"))):
        ax, err = axes[0][col], axes[1][col]
        ax.plot(direct[:, 0], direct[:, idx], "k-", lw=2.2, label="direct rendering")
        for key, label, style in curves:
            d = s[key]
            if not np.allclose(d[:, 0], direct[:, 0]):
                fail(f"{a.csv}: '{key[0]}' order {key[1]} has other azimuths than 'direct'")
            ax.plot(d[:, 0], d[:, idx], style, lw=1.3, label=label)
            err.plot(d[:, 0], d[:, idx] - direct[:, idx], style, lw=1.3, label=label)
        ax.set_ylabel(f"{name} ({unit}, left > 0)")
        ax.set_title(name)
        err.set_ylabel(f"{name} error ({unit})")
        err.set_xlabel("azimuth (deg, +90 = left)")
        err.axhline(0, color="k", lw=0.8)
        for x in (ax, err):
            x.grid(True, alpha=0.3)
            x.set_xticks(range(-180, 181, 30))
        ax.legend(fontsize=8)
    axes[1][0].axhspan(-1.5, 1.5, color="g", alpha=0.08)
    axes[1][1].axhspan(-50, 50, color="g", alpha=0.08)
    fig.suptitle(a.title)
    fig.tight_layout()
    save_figure(fig, a.out)


if __name__ == "__main__":
    main()

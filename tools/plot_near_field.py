#!/usr/bin/python3
"""Plot the near field's rendered cue changes against the rigid-sphere model's.

    build/release/tests/bench/near_field --csv near_field.csv
    /usr/bin/python3 tools/plot_near_field.py --csv near_field.csv --out near_field.png [--title T]

near_field.csv is what `near_field --csv` writes: one row per (distance_m, azimuth_deg) with
the rendered ILD in three bands (ild_lo_db 0.5-2 kHz, ild_mid_db 2-6 kHz, ild_hi_db 6-12 kHz)
and ITD (itd_us, below 1.5 kHz), the same rendered at the set's own distance (far_*), and
the sphere model's values at both distances (model_*, model_far_*). The figure plots, per
band and for the ITD, the change from the set's own distance against azimuth: rendered as
solid lines, the model's as dashed lines, one colour per distance. Azimuth is SOFA's:
counter-clockwise from ahead, +90 = left. Exit code 2 with a one-line message on bad input.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_common import fail, read_csv_rows, save_figure  # noqa: E402

CUES = [("ild_lo_db", "ILD change 0.5-2 kHz (dB)"), ("ild_mid_db", "ILD change 2-6 kHz (dB)"),
        ("ild_hi_db", "ILD change 6-12 kHz (dB)"), ("itd_us", "ITD change below 1.5 kHz (us)")]
COLUMNS = ["distance_m", "azimuth_deg"] + [p + c for c, _ in CUES for p in ("", "far_", "model_", "model_far_")]


def read(path):
    rows = read_csv_rows(path, COLUMNS, expected="near_field --csv output")
    data = {c: [] for c in COLUMNS}
    for line, r in enumerate(rows, start=2):
        for c in COLUMNS:
            try:
                data[c].append(float(r[c]))
            except ValueError:
                fail(f"{path}:{line}: field '{c}': not a number: '{r[c]}'")
    return {c: np.array(v) for c, v in data.items()}


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--csv", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--title", default="Near field: rendered (solid) against the rigid sphere (dashed)")
    a = p.parse_args()
    d = read(a.csv)
    fig, axes = plt.subplots(2, 2, figsize=(11, 7.5), sharex=True)
    distances = sorted(set(d["distance_m"]))
    colours = plt.cm.viridis(np.linspace(0.0, 0.85, len(distances)))
    for ax, (cue, label) in zip(axes.flat, CUES):
        for dist, colour in zip(distances, colours):
            m = d["distance_m"] == dist
            order = np.argsort(d["azimuth_deg"][m])
            az = d["azimuth_deg"][m][order]
            rendered = (d[cue] - d["far_" + cue])[m][order]
            model = (d["model_" + cue] - d["model_far_" + cue])[m][order]
            ax.plot(az, rendered, "-", color=colour, label=f"{dist:g} m")
            ax.plot(az, model, "--", color=colour)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
        ax.axhline(0.0, color="k", lw=0.5)
    for ax in axes[1]:
        ax.set_xlabel("azimuth (deg, 90 = left)")
        ax.set_xticks(range(0, 181, 30))
    axes[0][0].legend(title="distance", fontsize=8)
    fig.suptitle(a.title)
    fig.tight_layout()
    save_figure(fig, a.out)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plot rendered ITD and ILD against azimuth beside the SOFA data's.

    build/release/tests/bench/cue_accuracy --csv cues.csv
    /usr/bin/python3 tools/plot_cues.py --csv cues.csv --out cues.png [--title T]

cues.csv is what `cue_accuracy --csv` writes: one row per rendered 1-degree step
(elevation_deg, azimuth_deg, itd_us, itd_below_1500hz_us, ild_db) with the SOFA data's
cues (sofa_itd_us, sofa_ild_db) where the HRTF set was measured. The figure has one row
per elevation: ITD (broadband and below 1.5 kHz) and ILD against azimuth, rendered as
lines and measured as dots, and the rendered-minus-measured errors. Azimuth is SOFA's:
counter-clockwise from ahead, +90 = left. Exit code 2 with a one-line message on bad input.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_common import fail, read_csv_rows, save_figure  # noqa: E402

COLUMNS = ["elevation_deg", "azimuth_deg", "itd_us", "itd_below_1500hz_us", "ild_db", "sofa_itd_us", "sofa_ild_db"]


def read(path):
    rows = read_csv_rows(path, COLUMNS)
    data = {c: [] for c in COLUMNS}
    for line, r in enumerate(rows, start=2):
        for c in COLUMNS:
            v = r[c]
            if v == "" and c.startswith("sofa_"):
                data[c].append(np.nan)
                continue
            try:
                data[c].append(float(v))
            except ValueError:
                fail(f"{path}:{line}: field '{c}': not a number: '{v}'")
    return {c: np.array(v) for c, v in data.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--csv", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--title", default="Rendered interaural cues against the SOFA data")
    a = ap.parse_args()
    d = read(a.csv)
    elevations = sorted(set(d["elevation_deg"]), key=lambda e: (abs(e), e))
    fig, axes = plt.subplots(len(elevations), 3, figsize=(15, 3.6 * len(elevations)), squeeze=False)
    for row, el in zip(axes, elevations):
        m = d["elevation_deg"] == el
        az = d["azimuth_deg"][m]
        meas = ~np.isnan(d["sofa_itd_us"][m])
        ax = row[0]
        ax.plot(az, d["itd_us"][m], lw=1.2, label="rendered (broadband)")
        ax.plot(az, d["itd_below_1500hz_us"][m], lw=1.0, ls="--", label="rendered (< 1.5 kHz)")
        ax.plot(az[meas], d["sofa_itd_us"][m][meas], "k.", ms=4, label="SOFA data")
        ax.set_ylabel("ITD (us, left leads > 0)")
        ax.set_title(f"ITD, elevation {el:+.0f} deg")
        ax.legend(fontsize=8)
        ax = row[1]
        ax.plot(az, d["ild_db"][m], lw=1.2, label="rendered")
        ax.plot(az[meas], d["sofa_ild_db"][m][meas], "k.", ms=4, label="SOFA data")
        ax.set_ylabel("ILD (dB, left louder > 0)")
        ax.set_title(f"ILD, elevation {el:+.0f} deg")
        ax.legend(fontsize=8)
        ax = row[2]
        ax.plot(az[meas], d["itd_us"][m][meas] - d["sofa_itd_us"][m][meas], "o-", ms=3, label="ITD error (us)")
        ax.plot(az[meas], 10 * (d["ild_db"][m][meas] - d["sofa_ild_db"][m][meas]), "s-", ms=3,
                label="ILD error (dB x 10)")
        ax.axhspan(-10, 10, color="0.9", zorder=0, label="target: 10 us / 0.5 dB x 10 = 5")
        ax.axhline(5, color="0.6", lw=0.5)
        ax.axhline(-5, color="0.6", lw=0.5)
        ax.set_title("rendered minus measured, at measured azimuths")
        ax.legend(fontsize=8)
        for ax in row:
            ax.set_xlabel("azimuth (deg, SOFA: +90 = left)")
            ax.set_xlim(-180, 180)
            ax.set_xticks(range(-180, 181, 45))
            ax.grid(alpha=0.3)
    fig.suptitle(a.title)
    fig.tight_layout()
    save_figure(fig, a.out, dpi=90)
    print(f"wrote {a.out}")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plot the LED estimates of `earshot track calibrate` converging, step by step.

    /usr/bin/python3 tools/plot_calibration.py --iterations ITS.csv --out OUT.png [--true-focal 1280]

ITS.csv is what the led_calibration benchmark writes with --iterations: one row per
variant (fixed / focal), seed, round, step and LED with the estimate (mm, aligned to the
starting model), its distance to the true LED after a rigid alignment (err_mm), the RMS
residual and the focal length. The figure shows each LED's error against the adjustment's
step (round 1, labels from the starting model, then round 2, labels from the first
estimate), one line per seed and LED, for the focal length known and estimated, and the
focal length's error. Exit code 2 with a one-line message on bad input.
"""
import argparse
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from plot_common import fail, read_csv_rows, save_figure  # noqa: E402

COLUMNS = ("variant", "seed", "round", "iteration", "led", "err_mm", "rms_px", "focal_px")
LED_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:red")


def load(path):
    rows = read_csv_rows(path, COLUMNS, expected="the led_calibration benchmark's --iterations CSV")
    runs = defaultdict(list)  # (variant, seed, led) -> [(round, iteration, err, rms, focal)]
    for n, r in enumerate(rows):
        try:
            key = (r["variant"], int(r["seed"]), int(r["led"]))
            runs[key].append((int(r["round"]), int(r["iteration"]), float(r["err_mm"]), float(r["rms_px"]),
                              float(r["focal_px"])))
        except ValueError:
            fail(f"{path}:{n + 2}: a field is not a number")
    return runs


def steps(points):
    """Cumulative step index over both rounds (round 2 starts where round 1 ended)."""
    points = sorted(points)
    out, offset, last_round, last = [], 0, None, 0
    for rnd, it, *rest in points:
        if last_round is not None and rnd != last_round:
            offset = last
        out.append((offset + it, *rest))
        last, last_round = offset + it, rnd
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--iterations", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--true-focal", type=float, default=1280.0)
    a = ap.parse_args()
    runs = load(a.iterations)
    variants = [v for v in ("fixed", "focal") if any(k[0] == v for k in runs)]
    if not variants:
        fail(f"{a.iterations}: no rows of variant 'fixed' or 'focal'")
    ncols = len(variants) + ("focal" in variants)
    fig, axes = plt.subplots(1, ncols, figsize=(5.2 * ncols, 4.2), squeeze=False)
    seeds = sorted({k[1] for k in runs})
    for col, variant in enumerate(variants):
        ax = axes[0][col]
        for (v, seed, led), pts in runs.items():
            if v != variant:
                continue
            s = steps(pts)
            ax.plot([p[0] for p in s], [max(p[1], 1e-4) for p in s], color=LED_COLOURS[led % 4], lw=0.8, alpha=0.6,
                    marker=".", ms=3, label=f"LED {led}" if seed == seeds[0] else None)
        ax.axhline(0.5, color="k", ls="--", lw=0.8, label="target 0.5 mm")
        ax.set_yscale("log")
        ax.set_xlabel("adjustment step (round 1, then round 2)")
        ax.set_ylabel("LED error after rigid alignment (mm)")
        title = "focal known (1280 px)" if variant == "fixed" else "focal estimated (start +5 %)"
        ax.set_title(f"{title}, {len(seeds)} seeds")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    if "focal" in variants:
        ax = axes[0][ncols - 1]
        for (v, seed, led), pts in runs.items():
            if v != "focal" or led != 0:
                continue
            s = steps(pts)
            ax.plot([p[0] for p in s], [100.0 * (p[3] / a.true_focal - 1.0) for p in s], lw=0.8, marker=".", ms=3)
        ax.axhline(0.0, color="k", lw=0.8)
        ax.set_xlabel("adjustment step (round 1, then round 2)")
        ax.set_ylabel(f"focal length error (% of {a.true_focal:g} px)")
        ax.set_title("focal length, one line per seed")
        ax.grid(True, alpha=0.3)
    fig.suptitle("LED-model self-calibration: seated 60 s sessions, every starting LED 3 mm off")
    fig.tight_layout()
    save_figure(fig, a.out)


if __name__ == "__main__":
    main()

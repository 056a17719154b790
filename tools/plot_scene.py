#!/usr/bin/python3
"""Plot where a scene's sources go, in three projections around the listener.

    earshot scene paths --scene circles --out paths.csv [--step 0.05]
    /usr/bin/python3 tools/plot_scene.py --paths paths.csv --out circles.png [--title T] [--limit M]

PATHS.csv has columns t,source,x,y,z (seconds; metres in the audio world frame: +x right,
+y up, -z ahead). The figure shows the top view (x against ahead, -z), the front view
(x against y) and the side view (ahead, -z, against y), with the listener at the origin
facing ahead. A moving source is a line from its start (circle) to its end (triangle),
with a dot every second; a still one is a star. Exit code 2 with a one-line message on
bad input.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_common import fail, read_csv_rows, save_figure  # noqa: E402


def read_paths(path):
    rows = read_csv_rows(path, ("t", "source", "x", "y", "z"), expected="t,source,x,y,z from `earshot scene paths`")
    sources = {}
    for i, r in enumerate(rows):
        try:
            p = [float(r[c]) for c in ("t", "x", "y", "z")]
        except ValueError:
            fail(f"{path}:{i + 2}: not a number in t, x, y or z")
        sources.setdefault(r["source"], []).append(p)
    return {k: np.array(v) for k, v in sources.items()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--paths", required=True, help="CSV from `earshot scene paths`")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--title", default=None)
    ap.add_argument("--limit", type=float, default=None,
                    help="Show only +-LIMIT metres around the listener (default: everything)")
    a = ap.parse_args()
    if a.limit is not None and not a.limit > 0:
        fail(f"--limit: must be positive, got {a.limit}")
    sources = read_paths(a.paths)

    # (horizontal, vertical) as functions of (x, y, z), and their labels.
    views = [
        ("Top view (from above)", lambda p: (p[:, 1], -p[:, 3]), "x, right (m)", "-z, ahead (m)"),
        ("Front view (from behind the listener)", lambda p: (p[:, 1], p[:, 2]), "x, right (m)", "y, up (m)"),
        ("Side view (from the right)", lambda p: (-p[:, 3], p[:, 2]), "-z, ahead (m)", "y, up (m)"),
    ]
    fig, ax = plt.subplots(1, 3, figsize=(17, 6))
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for (title, proj, xl, yl), a_ in zip(views, ax):
        for k, (name, p) in enumerate(sources.items()):
            c = colors[k % len(colors)]
            h, v = proj(p)
            moving = np.ptp(p[:, 1:4], axis=0).max() > 1e-6
            if moving:
                # Earlier sources are drawn wider underneath, so shared paths stay visible.
                a_.plot(h, v, color=c, lw=1.2 + 3.0 * (len(sources) - 1 - k) / max(1, len(sources) - 1),
                        label=name, zorder=2 + k)
                t = p[:, 0]
                every = np.searchsorted(t, np.arange(t[0], t[-1] + 1e-9, 1.0))
                every = every[every < len(t)]
                a_.plot(h[every], v[every], ".", color=c, ms=4)
                a_.plot(h[0], v[0], "o", color=c, ms=7)
                a_.plot(h[-1], v[-1], "^", color=c, ms=7)
            else:
                a_.plot(h[0], v[0], "*", color=c, ms=12, label=f"{name} (still)")
        # The listener: a head at the origin with its nose ahead (or up in the front view).
        a_.add_patch(plt.Circle((0, 0), 0.09, color="black", fill=False, lw=1.5))
        if title.startswith("Front"):
            a_.plot([0], [0], "k+", ms=8)
        else:
            a_.plot([0, 0.0 if title.startswith("Side") else 0], [0, 0], "k")
            a_.annotate("", xy=(0.35, 0) if title.startswith("Side") else (0, 0.35), xytext=(0, 0),
                        arrowprops=dict(arrowstyle="->", color="black"))
        a_.set_title(title)
        a_.set_xlabel(xl)
        a_.set_ylabel(yl)
        if a.limit is not None:
            a_.set_xlim(-a.limit, a.limit)
            a_.set_ylim(-a.limit, a.limit)
            a_.set_aspect("equal", adjustable="box")
        else:
            a_.set_aspect("equal", adjustable="datalim")
        a_.grid(alpha=0.3)
    handles, labels = ax[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="lower center", fontsize=9, ncol=min(len(labels), 7))
    t_end = max(p[-1, 0] for p in sources.values())
    fig.suptitle(a.title or f"{a.paths}: {len(sources)} sources, {t_end:g} s (o start, ^ end, dots every second)")
    fig.tight_layout(rect=(0, 0.07, 1, 0.94))
    save_figure(fig, a.out, dpi=90)


if __name__ == "__main__":
    main()

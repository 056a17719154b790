#!/usr/bin/python3
"""Plot the renderer throughput benchmark: CPU per source against the number of sources.

    build/release/tests/bench/render_throughput --sources 1,8,32,64,128,256,512,1024 --csv moving.csv
    /usr/bin/python3 tools/plot_throughput.py --csv moving.csv --out throughput.png [--title T]

moving.csv is what `render_throughput --csv` writes: sources, moving (1 or 0), earshot_rtf,
openal_rtf (realtime factors; 0 where a renderer was not run). The left panel is the
realtime factor against N (log-log, the realtime line marked); the right one is the cost of
one source for one 128-frame block in microseconds, for both renderers. Exit code 2 with a
one-line message on bad input.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from plot_common import fail, read_csv_rows, save_figure  # noqa: E402

BLOCK_US = 1e6 * 128 / 48000


def read(path):
    rows = read_csv_rows(path)
    out = []
    for i, r in enumerate(rows, start=2):
        try:
            out.append((int(r["sources"]), float(r["earshot_rtf"]), float(r["openal_rtf"])))
        except (KeyError, TypeError, ValueError):
            fail(f"{path}:{i}: expected columns sources, earshot_rtf, openal_rtf with numbers")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--csv", required=True)
    ap.add_argument("--out", required=True)
    ap.add_argument("--title", default="Moving HRTF sources, 48 kHz, 128-frame blocks, one core")
    a = ap.parse_args()
    rows = read(a.csv)
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
    for idx, name, style in ((1, "Earshot (MIT KEMAR, 558 taps)", "o-"), (2, "OpenAL Soft 1.19 (32 taps)", "s--")):
        pts = [(r[0], r[idx]) for r in rows if r[idx] > 0]
        if not pts:
            continue
        n, rtf = zip(*pts)
        left.plot(n, rtf, style, label=name)
        right.plot(n, [BLOCK_US / (x * k) for x, k in zip(rtf, n)], style, label=name)
    left.axhline(1.0, color="grey", lw=0.8)
    left.text(1, 1.05, "realtime", color="grey", fontsize=8)
    left.set(xscale="log", yscale="log", xlabel="sources", ylabel="realtime factor (audio s / CPU s)")
    right.set(xscale="log", xlabel="sources", ylabel="µs per source and block", ylim=(0, None))
    for ax in (left, right):
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(a.title)
    fig.tight_layout()
    save_figure(fig, a.out, dpi=110)


if __name__ == "__main__":
    main()

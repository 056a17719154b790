#!/usr/bin/python3
"""Plot estimated against true head pose over time, like the thesis's figures 73-76.

    /usr/bin/python3 tools/plot_poses.py --dots DOTS.csv --poses POSES.csv --out OUT.png [--title T]
    /usr/bin/python3 tools/plot_poses.py --dots DOTS.csv --known RAW.csv DEFAULT.csv [MORE.csv ...]
                                         [--labels raw,default,...] --out OUT.png [--title T]

DOTS.csv is a simulated Dots CSV (with gt_* ground-truth columns), POSES.csv the output
of `earshot track solve`. The figure shows translation (mm) and rotation (yaw, pitch,
roll in degrees, R = Ry(yaw) Rx(pitch) Rz(roll) in the camera frame) estimated and true,
and the translation and rotation errors over time; frames that are not `tracking` are
shaded. Exit code 2 with a one-line message on bad input.

--known: what the listener hears. The rotation error of every row written, against what
the camera could know (the truth while 3+ LEDs are seen, else the truth of the last frame
with 3+ LEDs), for each Poses CSV given (the first one raw LM's, `--filter none`), beside
a hold-the-last-tracked-pose baseline made from the first; frames with fewer than 3 LEDs
seen are shaded.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_common import fail, read_csv_rows, save_figure  # noqa: E402


def read_columns(path, names):
    rows = read_csv_rows(path, names)
    out = {}
    for n in names:
        if n == "state":
            out[n] = np.array([r[n] for r in rows])
            continue
        try:
            out[n] = np.array([float(r[n]) for r in rows])
        except ValueError:
            bad = next(i for i, r in enumerate(rows) if not _is_float(r[n]))
            fail(f"{path}:{bad + 2}: field '{n}': not a number: '{rows[bad][n]}'")
    return out


def _is_float(s):
    try:
        float(s)
        return True
    except ValueError:
        return False


def quat_to_matrix(w, x, y, z):
    n = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    R = np.empty((len(w), 3, 3))
    R[:, 0, 0] = 1 - 2 * (y * y + z * z)
    R[:, 0, 1] = 2 * (x * y - w * z)
    R[:, 0, 2] = 2 * (x * z + w * y)
    R[:, 1, 0] = 2 * (x * y + w * z)
    R[:, 1, 1] = 1 - 2 * (x * x + z * z)
    R[:, 1, 2] = 2 * (y * z - w * x)
    R[:, 2, 0] = 2 * (x * z - w * y)
    R[:, 2, 1] = 2 * (y * z + w * x)
    R[:, 2, 2] = 1 - 2 * (x * x + y * y)
    return R


def ypr_deg(R):
    """Yaw, pitch, roll of R = Ry(yaw) Rx(pitch) Rz(roll)."""
    pitch = np.arcsin(np.clip(-R[:, 1, 2], -1, 1))
    yaw = np.arctan2(R[:, 0, 2], R[:, 2, 2])
    roll = np.arctan2(R[:, 1, 0], R[:, 1, 1])
    return np.degrees(np.stack([yaw, pitch, roll], axis=1))


def angle_deg(Ra, Rb):
    rel = np.einsum("nji,njk->nik", Ra, Rb)
    return np.degrees(np.arccos(np.clip((np.trace(rel, axis1=1, axis2=2) - 1) / 2, -1, 1)))


def known_figure(a):
    """--known: every row's rotation error against what the camera could know."""
    gt = read_columns(a.dots, ["t_s", "gt_qw", "gt_qx", "gt_qy", "gt_qz", "gt_led1", "gt_led2", "gt_led3", "gt_led4"])
    t = gt["t_s"]
    n = len(t)
    leds = sum((gt[f"gt_led{k}"] > 0).astype(int) for k in range(1, 5))
    Rt = quat_to_matrix(gt["gt_qw"], gt["gt_qx"], gt["gt_qy"], gt["gt_qz"])
    known = np.empty_like(Rt)
    have = np.zeros(n, dtype=bool)
    last = None
    for i in range(n):
        if leds[i] >= 3:
            last = Rt[i]
        if last is not None:
            known[i] = last
            have[i] = True
    labels = a.labels.split(",") if a.labels else [f"poses {k + 1}" for k in range(len(a.known))]
    if len(labels) != len(a.known):
        fail(f"--labels: {len(labels)} labels for {len(a.known)} Poses CSVs")
    series = []
    for path, label in zip(a.known, labels):
        est = read_columns(path, ["t_s", "state", "qw", "qx", "qy", "qz"])
        if len(est["t_s"]) != n:
            fail(f"{path}: {len(est['t_s'])} rows but {a.dots} has {n}: not the same run")
        series.append((label, est))
    # The hold-last baseline: the first (raw) row's tracked poses, held.
    raw = series[0][1]
    Rr = quat_to_matrix(raw["qw"], raw["qx"], raw["qy"], raw["qz"])
    Rh = Rr.copy()
    tracked = raw["state"] == "tracking"
    first = np.argmax(tracked) if tracked.any() else n
    for i in range(n):
        if i > 0 and not tracked[i]:
            Rh[i] = Rh[i - 1]
    fig, ax = plt.subplots(2, 1, figsize=(14, 8), sharex=True)
    styles = [("tab:gray", 1.2), ("tab:blue", 0.9), ("tab:green", 0.9), ("tab:purple", 0.9)]
    curves = [(f"hold-last ({labels[0]}'s tracked poses, held)", Rh, np.arange(n) >= first, "black", 1.6)]
    for k, (label, est) in enumerate(series):
        c, w = styles[k % len(styles)]
        # Rows from the first pose on (before it the file holds no pose, only its place).
        written = np.maximum.accumulate(est["state"] == "tracking")
        curves.append((label, quat_to_matrix(est["qw"], est["qx"], est["qy"], est["qz"]), written, c, w))
    for label, R, written, c, w in curves:
        e = angle_deg(known, R)
        e[~(have & written)] = np.nan
        p99 = np.nanpercentile(e, 99) if np.isfinite(e).any() else np.nan
        for a_ in ax:
            a_.plot(t, e, color=c, lw=w, label=f"{label}: p99 {p99:.1f}, max {np.nanmax(e):.1f} deg")
    ax[0].set_ylabel("error (deg)")
    ax[0].set_title("Rotation error of every row against what the camera could know")
    ax[1].set_ylabel("error (deg), log")
    ax[1].set_yscale("log")
    ax[1].set_ylim(1e-2, 200)
    ax[1].set_xlabel("time (s)")
    for a_ in ax:
        a_.fill_between(t, 0, 1, where=leds < 3, color="0.88", transform=a_.get_xaxis_transform(), lw=0,
                        label="fewer than 3 LEDs seen")
        a_.legend(loc="upper right", fontsize=8)
        a_.grid(alpha=0.3)
    fig.suptitle(a.title or f"{', '.join(a.known)} against {a.dots}")
    fig.tight_layout()
    save_figure(fig, a.out, dpi=90)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dots", required=True, help="Dots CSV with ground truth (earshot track simulate)")
    ap.add_argument("--poses", help="Poses CSV (earshot track solve)")
    ap.add_argument("--known", nargs="+", help="Poses CSVs, raw LM's first: every row against what the camera knew")
    ap.add_argument("--labels", default=None, help="with --known: comma-separated names of the Poses CSVs")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--title", default=None)
    a = ap.parse_args()
    if a.known:
        known_figure(a)
        return
    if not a.poses:
        fail("--poses or --known is required")

    gt = read_columns(a.dots, ["t_s", "gt_tx_mm", "gt_ty_mm", "gt_tz_mm", "gt_qw", "gt_qx", "gt_qy", "gt_qz"])
    est = read_columns(a.poses, ["t_s", "state", "tx_mm", "ty_mm", "tz_mm", "qw", "qx", "qy", "qz"])
    n = len(gt["t_s"])
    if len(est["t_s"]) != n:
        fail(f"{a.poses}: {len(est['t_s'])} rows but {a.dots} has {n}: not the same run")

    t = gt["t_s"]
    Rt = quat_to_matrix(gt["gt_qw"], gt["gt_qx"], gt["gt_qy"], gt["gt_qz"])
    Re = quat_to_matrix(est["qw"], est["qx"], est["qy"], est["qz"])
    tt = np.stack([gt["gt_tx_mm"], gt["gt_ty_mm"], gt["gt_tz_mm"]], axis=1)
    te = np.stack([est["tx_mm"], est["ty_mm"], est["tz_mm"]], axis=1)
    tracking = est["state"] == "tracking"
    rel = np.einsum("nji,njk->nik", Rt, Re)
    rot_err = np.degrees(np.arccos(np.clip((np.trace(rel, axis1=1, axis2=2) - 1) / 2, -1, 1)))
    trans_err = np.linalg.norm(te - tt, axis=1)
    rot_err[~tracking] = np.nan
    trans_err[~tracking] = np.nan
    te_plot = te.copy()
    te_plot[~tracking] = np.nan
    ypr_t, ypr_e = ypr_deg(Rt), ypr_deg(Re)
    ypr_e[~tracking] = np.nan

    fig, ax = plt.subplots(3, 2, figsize=(14, 10), sharex=True)
    colors = ["tab:red", "tab:green", "tab:blue"]
    for i, name in enumerate(["x", "y", "z"]):
        ax[0, 0].plot(t, tt[:, i], color="black", lw=0.8)
        ax[0, 0].plot(t, te_plot[:, i], color=colors[i], lw=0.8, label=f"t{name} estimated")
    ax[0, 0].set_ylabel("translation (mm)")
    ax[0, 0].set_title("Translation: estimated (colour) vs true (black)")
    for i, name in enumerate(["yaw", "pitch", "roll"]):
        ax[0, 1].plot(t, ypr_t[:, i], color="black", lw=0.8)
        ax[0, 1].plot(t, ypr_e[:, i], color=colors[i], lw=0.8, label=f"{name} estimated")
    ax[0, 1].set_ylabel("angle (deg)")
    ax[0, 1].set_title("Rotation: estimated (colour) vs true (black)")
    for i, name in enumerate(["x", "y", "z"]):
        ax[1, 0].plot(t, te_plot[:, i] - tt[:, i], color=colors[i], lw=0.6, label=f"t{name} error")
    ax[1, 0].set_ylabel("error (mm)")
    ax[1, 0].set_title("Translation error per axis")
    for i, name in enumerate(["yaw", "pitch", "roll"]):
        d = (ypr_e[:, i] - ypr_t[:, i] + 180) % 360 - 180
        ax[1, 1].plot(t, d, color=colors[i], lw=0.6, label=f"{name} error")
    ax[1, 1].set_ylabel("error (deg)")
    ax[1, 1].set_title("Rotation error per angle")
    ax[2, 0].plot(t, trans_err, color="tab:purple", lw=0.6, label="|t error|")
    ax[2, 0].set_ylabel("|error| (mm)")
    ax[2, 0].set_title(f"Translation error: RMS {np.sqrt(np.nanmean(trans_err ** 2)):.2f} mm")
    ax[2, 1].plot(t, rot_err, color="tab:purple", lw=0.6, label="rotation error angle")
    ax[2, 1].set_ylabel("error angle (deg)")
    ax[2, 1].set_title(f"Rotation error: RMS {np.sqrt(np.nanmean(rot_err ** 2)):.3f} deg")
    for a_ in ax.flat:
        # Shade frames that are not tracked (predicted or lost).
        a_.fill_between(t, 0, 1, where=~tracking, color="0.85", transform=a_.get_xaxis_transform(), lw=0,
                        label="not tracking")
        a_.legend(loc="upper right", fontsize=7, ncol=2)
        a_.grid(alpha=0.3)
    for a_ in ax[2]:
        a_.set_xlabel("time (s)")
    fig.suptitle(a.title or f"{a.poses} against {a.dots}")
    fig.tight_layout()
    save_figure(fig, a.out, dpi=90)


if __name__ == "__main__":
    main()

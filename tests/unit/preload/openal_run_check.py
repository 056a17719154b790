#!/usr/bin/env python3
"""Runs a real OpenAL program with and without earshot-openal-run and checks
that what it plays follows the head: OpenAL Soft's `wave` backend (HRTF on)
writes the program's output to a WAV, a thread sends the head pose as OSC
(/earshot/ypr) to the shim's tracker (osc:PORT), and the ILD (left minus
right level, dB, median over 100 ms windows) is measured per run:

  none      no shim (poses are sent but nobody listens): the baseline B,
            for a source ahead |B| < 1 dB
  yaw 0     shim, head straight:        |ILD - B| <= 1 dB + 3 s
  yaw +60   shim, head turned left:      ILD <= B - (3 dB + 3 s)   (source heard on the right)
  yaw -60   shim, head turned right:     ILD >= B + (3 dB + 3 s)

where s is the spread (standard deviation) of the baseline's windows.
Prints one line per run; exits 1 naming the program and condition that failed.

usage: openal_run_check.py --launcher PATH --program pyglet|gst|gst-mono|mpg123
                           --work DIR --port N [--conditions none,0,60,-60]
                           [--pyglet-script PATH] [--duration S] [--place MODE]
"""
import argparse
import os
import shutil
import socket
import struct
import subprocess
import sys
import threading

import numpy as np

RUN_TIMEOUT_S = 40


def osc_message(path, *floats):
    def pad(b):
        return b + b"\0" * (4 - len(b) % 4)
    return pad(path.encode()) + pad(("," + "f" * len(floats)).encode()) + b"".join(struct.pack(">f", f) for f in floats)


class PoseSender:
    """Sends /earshot/ypr YAW 0 0 to 127.0.0.1:PORT every 20 ms until stopped."""

    def __init__(self, port, yaw_deg):
        self.port, self.msg = port, osc_message("/earshot/ypr", yaw_deg, 0.0, 0.0)
        self.stop = threading.Event()
        self.thread = threading.Thread(target=self.run, daemon=True)

    def run(self):
        with socket.socket(socket.AF_INET, socket.SOCK_DGRAM) as s:
            while not self.stop.wait(0.02):
                s.sendto(self.msg, ("127.0.0.1", self.port))

    def __enter__(self):
        self.thread.start()
        return self

    def __exit__(self, *exc):
        self.stop.set()
        self.thread.join()


def read_wav(path):
    """Stereo samples (float) and rate of a PCM/float WAV (plain or extensible)."""
    with open(path, "rb") as f:
        d = f.read()
    if d[0:4] != b"RIFF" or d[8:12] != b"WAVE":
        raise ValueError(f"{path}: not a RIFF/WAVE file")
    pos, fmt = 12, None
    while pos + 8 <= len(d):
        cid, size = d[pos:pos + 4], struct.unpack_from("<I", d, pos + 4)[0]
        if cid == b"fmt ":
            _, ch, rate, _, _, bits = struct.unpack_from("<HHIIHH", d, pos + 8)
            fmt = (ch, rate, bits)
        elif cid == b"data":
            if fmt is None:
                raise ValueError(f"{path}: data before fmt")
            ch, rate, bits = fmt
            if ch != 2 or bits not in (16, 32):
                raise ValueError(f"{path}: {ch} channels of {bits} bits, expected stereo 16 or 32")
            frame = ch * bits // 8
            body = d[pos + 8:pos + 8 + size]  # the wave backend may leave the size 0 when killed: read what is there
            body = d[pos + 8:] if size == 0 else body
            body = body[:len(body) // frame * frame]
            x = np.frombuffer(body, dtype=np.int16 if bits == 16 else np.float32).reshape(-1, 2).astype(float)
            return x, rate
        pos += 8 + size + (size & 1)
    raise ValueError(f"{path}: no data chunk")


def ild_windows(x, rate, skip_s=0.3, win_s=0.1):
    """Per 100 ms window with sound in it (above -60 dBFS): left minus right level, dB."""
    win, out = int(win_s * rate), []
    full = 32768.0 if np.abs(x).max() > 2.0 else 1.0
    for i in range(int(skip_s * rate), len(x) - win + 1, win):
        w = x[i:i + win] / full
        el, er = (w[:, 0] ** 2).mean(), (w[:, 1] ** 2).mean()
        if 10 * np.log10((el + er) / 2 + 1e-20) < -60:
            continue
        out.append(10 * np.log10(el + 1e-20) - 10 * np.log10(er + 1e-20))
    return np.array(out)


def make_mp3(work, duration):
    path = os.path.join(work, "noise.mp3")
    buffers = int(duration * 44100 / 1024) + 1
    subprocess.run(["gst-launch-1.0", "-q", "audiotestsrc", "wave=pink-noise", f"num-buffers={buffers}", "!",
                    "audio/x-raw,channels=2,rate=44100", "!", "lamemp3enc", "!", "filesink", f"location={path}"],
                   check=True, timeout=RUN_TIMEOUT_S)
    return path


def program_command(args, work):
    buffers = int(args.duration * 44100 / 1024) + 1
    gst = ["gst-launch-1.0", "-q", "audiotestsrc", "wave=pink-noise", f"num-buffers={buffers}", "!"]
    if args.program == "pyglet":
        return [sys.executable, args.pyglet_script, str(args.duration)]
    if args.program == "gst":
        return gst + ["audio/x-raw,channels=2,rate=44100", "!", "openalsink"]
    if args.program == "gst-mono":
        return gst + ["audio/x-raw,channels=1,rate=44100", "!", "openalsink"]
    if args.program == "mpg123":
        return ["mpg123", "-q", "-o", "openal", make_mp3(work, args.duration)]
    raise ValueError(args.program)


def run(args, work, command, condition):
    """One run; returns the ILD windows of what the program played."""
    wav = os.path.join(work, f"{args.program}_{condition}.wav")
    conf = os.path.join(work, f"alsoft_{condition}.conf")
    with open(conf, "w") as f:  # OpenAL Soft 1.19's keys (alsoftrc.sample)
        f.write(f"[general]\ndrivers = wave\nchannels = stereo\nstereo-mode = headphones\nhrtf = true\n"
                f"[wave]\nfile = {wav}\n")
    if os.path.exists(wav):
        os.remove(wav)
    env = dict(os.environ, ALSOFT_CONF=conf, ALSOFT_DRIVERS="wave")
    env.pop("LD_PRELOAD", None)
    yaw = 60.0 if condition == "none" else float(condition)
    full = command if condition == "none" else \
        [args.launcher, "--tracker", f"osc:{args.port}"] + (["--place", args.place] if args.place else []) + ["--"] + command
    with PoseSender(args.port, yaw):
        p = subprocess.run(full, env=env, cwd=work, capture_output=True, text=True, timeout=RUN_TIMEOUT_S)
    if p.returncode != 0:
        sys.exit(f"{args.program} ({condition}): exit {p.returncode}: {p.stdout} {p.stderr}")
    if args.program == "pyglet" and "readback ok" not in p.stdout:
        sys.exit(f"{args.program} ({condition}): no 'readback ok': {p.stdout} {p.stderr}")
    if not os.path.exists(wav):
        sys.exit(f"{args.program} ({condition}): OpenAL Soft wrote no {wav}: {p.stderr}")
    x, rate = read_wav(wav)
    ild = ild_windows(x, rate)
    if len(ild) < 5:
        sys.exit(f"{args.program} ({condition}): only {len(ild)} windows with sound in {wav}")
    return ild


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--launcher", required=True)
    ap.add_argument("--program", required=True, choices=["pyglet", "gst", "gst-mono", "mpg123"])
    ap.add_argument("--work", required=True)
    ap.add_argument("--port", type=int, required=True)
    ap.add_argument("--conditions", default="none,0,60,-60")
    ap.add_argument("--pyglet-script")
    ap.add_argument("--duration", type=float, default=1.5)
    ap.add_argument("--place", choices=["none", "stereo", "all"], help="earshot-openal-run --place (default: its own)")
    ap.add_argument("--report-only", action="store_true", help="measure and print, check nothing")
    args = ap.parse_args()
    for tool in {"pyglet": [], "gst": ["gst-launch-1.0"], "gst-mono": ["gst-launch-1.0"],
                 "mpg123": ["mpg123", "gst-launch-1.0"]}[args.program]:
        if not shutil.which(tool):
            sys.exit(f"{tool} is not installed (scripts/install-deps.sh)")
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    command = program_command(args, args.work)

    conditions = args.conditions.split(",")
    if "none" not in conditions:
        conditions = ["none"] + conditions  # every check is against the baseline
    results = {c: run(args, args.work, command, c) for c in conditions}
    base = results["none"]
    b, s = float(np.median(base)), float(np.std(base))
    tol, turn = 1.0 + 3 * s, 3.0 + 3 * s
    failures = []
    for c, ild in results.items():
        m = float(np.median(ild))
        print(f"{args.program:8s} {'no shim' if c == 'none' else 'shim yaw ' + c:14s} "
              f"ILD {m:+7.2f} dB (windows {len(ild)}, spread {np.std(ild):.2f} dB)")
        if c == "none":
            ok = abs(m) < 1.0
            want = "|ILD| < 1 dB: the program's source is ahead"
        elif float(c) == 0:
            ok, want = abs(m - b) <= tol, f"within {tol:.2f} dB of the baseline {b:+.2f}"
        elif float(c) > 0:
            ok, want = m <= b - turn, f"<= {b - turn:+.2f} dB (head left: source on the right)"
        else:
            ok, want = m >= b + turn, f">= {b + turn:+.2f} dB (head right: source on the left)"
        if not ok:
            failures.append(f"{args.program} {c}: ILD {m:+.2f} dB, expected {want}")
    if failures and not args.report_only:
        sys.exit("\n".join(failures))


if __name__ == "__main__":
    main()

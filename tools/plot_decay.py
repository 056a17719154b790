#!/usr/bin/python3
"""Plot energy decay curves per band of reverb impulse responses read from WAV files.

    /usr/bin/python3 tools/plot_decay.py --wav IR.wav [--wav IR2.wav ...] [--label L ...] --out OUT.png
        [--decay-time S] [--hf-ratio R] [--hf-ref HZ] [--title T]

Each WAV holds an impulse response (mono or stereo; channels' energies are summed), e.g. as
written by `reverb_decay --wav-dir DIR`. Three panels: the 500 Hz and 1 kHz octave bands
and the third octave at --hf-ref (default 5000 Hz), filtered as reverb_decay does
(Butterworth edges, 4th order for octaves, 8th for the third octave). Each curve is the
Schroeder backward integral in dB; the legend gives its T30 RT60. With --decay-time (and
--hf-ratio) the target decay is drawn dashed from the curve's -5 dB point. Exit code 2
with a one-line message on bad input.
"""
import argparse
import struct

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from plot_common import fail, save_figure  # noqa: E402


def read_wav(path):
    """Samples (frames x channels, float) and rate of a PCM 16/24/32-bit or float WAV."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        fail(f"{path}: cannot open: {e.strerror}")
    if len(data) < 12 or data[:4] != b"RIFF" or data[8:12] != b"WAVE":
        fail(f"{path}: not a WAV file")
    pos, fmt, samples = 12, None, None
    while pos + 8 <= len(data):
        cid, size = data[pos:pos + 4], struct.unpack("<I", data[pos + 4:pos + 8])[0]
        body = data[pos + 8:pos + 8 + size]
        if cid == b"fmt ":
            tag, ch, rate, _, _, bits = struct.unpack("<HHIIHH", body[:16])
            if tag == 0xFFFE and len(body) >= 26:
                tag = struct.unpack("<H", body[24:26])[0]  # WAVE_FORMAT_EXTENSIBLE sub-format
            fmt = (tag, ch, rate, bits)
        elif cid == b"data":
            samples = body
        pos += 8 + size + (size & 1)
    if fmt is None or samples is None:
        fail(f"{path}: missing fmt or data chunk")
    tag, ch, rate, bits = fmt
    if tag == 3 and bits == 32:
        x = np.frombuffer(samples[: len(samples) // 4 * 4], dtype="<f4").astype(np.float64)
    elif tag == 1 and bits == 16:
        x = np.frombuffer(samples[: len(samples) // 2 * 2], dtype="<i2") / 32768.0
    elif tag == 1 and bits == 24:
        b = np.frombuffer(samples[: len(samples) // 3 * 3], dtype=np.uint8).reshape(-1, 3).astype(np.int32)
        v = b[:, 0] | (b[:, 1] << 8) | (b[:, 2] << 16)
        x = np.where(v >= 1 << 23, v - (1 << 24), v) / float(1 << 23)
    elif tag == 1 and bits == 32:
        x = np.frombuffer(samples[: len(samples) // 4 * 4], dtype="<i4") / 2147483648.0
    else:
        fail(f"{path}: unsupported sample format (tag {tag}, {bits} bits)")
    if len(x) < ch * 16:
        fail(f"{path}: too short")
    return x[: len(x) // ch * ch].reshape(-1, ch), rate


def butterworth(fc, fs, order, highpass):
    """Biquad sections (b, a) of a Butterworth edge, bilinear transform pre-warped at fc."""
    k = 1.0 / np.tan(np.pi * fc / fs)
    out = []
    for i in range(order // 2):
        d = 2.0 * np.sin(np.pi * (2 * i + 1) / (2 * order))
        n2, n1, n0 = (1.0, 0.0, 0.0) if highpass else (0.0, 0.0, 1.0)
        a0 = k * k + d * k + 1
        b = np.array([n2 * k * k + n1 * k + n0, 2 * (n0 - n2 * k * k), n2 * k * k - n1 * k + n0]) / a0
        a = np.array([1.0, 2 * (1 - k * k) / a0, (k * k - d * k + 1) / a0])
        out.append((b, a))
    return out


def band_energy(x, fs, lo, hi, order):
    """Energy (summed over channels) of x through the band, filtered in the frequency domain
    with the sections' exact response; zero padding keeps the filters' tails from wrapping."""
    n = 1 << int(np.ceil(np.log2(2 * len(x))))
    X = np.fft.rfft(x, n, axis=0)
    z = np.exp(-2j * np.pi * np.fft.rfftfreq(n) )
    H = np.ones_like(z)
    for b, a in butterworth(lo, fs, order, True) + butterworth(hi, fs, order, False):
        H *= (b[0] + b[1] * z + b[2] * z * z) / (a[0] + a[1] * z + a[2] * z * z)
    y = np.fft.irfft(X * H[:, None], n, axis=0)[: len(x)]
    return np.sum(y * y, axis=1)


def edc_db(e):
    c = np.cumsum(e[::-1])[::-1]
    with np.errstate(divide="ignore"):
        return 10 * np.log10(np.maximum(c / c[0], 1e-40))


def t30(edc, fs):
    i5 = np.argmax(edc <= -5)
    i35 = np.argmax(edc <= -35)
    if edc[-1] > -35 or i35 <= i5 + 2:
        return None, None
    t = np.arange(i5, i35 + 1) / fs
    slope, icpt = np.polyfit(t, edc[i5:i35 + 1], 1)
    return (-60.0 / slope if slope < 0 else None), i5 / fs


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--wav", action="append", required=True, help="impulse response WAV (repeatable)")
    ap.add_argument("--label", action="append", default=[], help="legend label per --wav")
    ap.add_argument("--out", required=True, help="PNG to write")
    ap.add_argument("--decay-time", type=float, default=None, help="target RT60 (s) at mid frequencies")
    ap.add_argument("--hf-ratio", type=float, default=None, help="target decay ratio at --hf-ref")
    ap.add_argument("--hf-ref", type=float, default=5000.0, help="high band centre (Hz)")
    ap.add_argument("--title", default=None)
    a = ap.parse_args()
    if a.label and len(a.label) != len(a.wav):
        fail(f"{len(a.label)} --label for {len(a.wav)} --wav")
    labels = a.label or a.wav

    k3 = 2 ** (1 / 6)
    bands = [("500 Hz octave", 500 / np.sqrt(2), 500 * np.sqrt(2), 4, 1.0),
             ("1 kHz octave", 1000 / np.sqrt(2), 1000 * np.sqrt(2), 4, 1.0),
             (f"{a.hf_ref:g} Hz third octave", a.hf_ref / k3, a.hf_ref * k3, 8, a.hf_ratio)]
    irs = [read_wav(p) for p in a.wav]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.8), sharey=True)
    colors = ["tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple"]
    t_end = 0.0
    for j, (title, lo, hi, order, ratio) in enumerate(bands):
        for i, ((x, fs), label) in enumerate(zip(irs, labels)):
            if hi >= fs / 2:
                fail(f"{a.wav[i]}: band {title} above Nyquist at {fs} Hz")
            edc = edc_db(band_energy(x, fs, lo, hi, order))
            t = np.arange(len(edc)) / fs
            t_end = max(t_end, t[-1])
            rt, t5 = t30(edc, fs)
            txt = f"{label}: T30 {rt:.2f} s" if rt else f"{label}: T30 n/a"
            ax[j].plot(t, edc, color=colors[i % len(colors)], lw=1.0, label=txt)
            if a.decay_time and ratio and t5 is not None:
                target = a.decay_time * ratio
                tt = np.array([t5, t5 + target * 95 / 60])
                ax[j].plot(tt, -5 - 60 * (tt - t5) / target, color=colors[i % len(colors)], ls="--", lw=0.8)
        tgt = f", target {a.decay_time * ratio:.2f} s (dashed)" if a.decay_time and ratio else ""
        ax[j].set_title(title + tgt, fontsize=10)
        ax[j].set_xlabel("time (s)")
        ax[j].grid(alpha=0.3)
        ax[j].legend(loc="upper right", fontsize=8)
        ax[j].axhspan(-35, -5, color="0.93", lw=0)  # the T30 fit range
    ax[0].set_ylabel("energy decay (dB)")
    ax[0].set_ylim(-100, 3)
    for a_ in ax:
        a_.set_xlim(0, t_end)
    fig.suptitle(a.title or ", ".join(a.wav))
    fig.tight_layout()
    save_figure(fig, a.out, dpi=90)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""A second HRTF set for the Ambisonic decoder's measurements: a rigid sphere, as a SOFA file.

    /usr/bin/python3 tools/ambi_sphere_sofa.py --out /tmp/sphere.sofa [--rate 44100] [--radius 0.09]
        [--ear-azimuth 100] [--ear-elevation -10] [--ring 7.5] [--length 256]

The decoder's design was tuned on MIT KEMAR (docs/AMBISONICS.md); this set is what it is checked
on without tuning: another head (a rigid sphere, radius 9 cm, the ears at +-100 deg azimuth and
-10 deg elevation, behind and below the sphere's equator as on a real head), another grid and
another rate (44.1 kHz; the renderer resamples).

The responses: the exact scattering of a plane wave by a rigid sphere at the ear's point of the
surface (Rayleigh's series, as in Duda and Martens 1998, JASA 104(5)):

    H(f, theta) = (1 / mu^2) sum_n i^(n+1) (2n + 1) P_n(-cos theta) / h_n'(mu),  mu = 2 pi f a / c,

h_n the spherical Hankel function of the first kind (time dependence exp(-i omega t), conjugated
here for exp(+i omega t)), theta the angle between the source direction and the ear (so -cos
theta: the series' angle is from the wave's direction of travel), relative to
the pressure the wave would have at the sphere's centre; the series to n = mu + 30. The
responses are delayed by 0.5 ms plus a / c (so the ear facing the source, which the wave reaches
a / c early, is causal), brought to time by an inverse FFT at 4x the length and cut to --length
samples with a half-Hann fade over the last quarter; above 0.45 x the rate they are faded out
(an ideal sphere has energy there that no measured set keeps).

The grid: a horizontal ring every --ring degrees (what ambi_cues measures), rings at elevations
+-15, +-30, ... +-75 deg with about cos(elevation) times as many directions, and the poles: the
whole sphere (KEMAR stops at -40 deg). Written by tests/fixtures/make_sofa.py's SOFA writer
(SimpleFreeFieldHRIR, 1.5 m, python3-netcdf4).
Exit code 2 with a one-line message on bad input.
"""
import argparse
import math
import os
import sys

import numpy as np
from scipy.special import eval_legendre, spherical_jn, spherical_yn

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "fixtures"))
import make_sofa  # noqa: E402  (the project's SOFA writer)

C = 343.0


def grid(ring_deg):
    dirs = []
    for el in np.arange(-75.0, 76.0, 15.0):
        n = int(round(360.0 / ring_deg)) if el == 0 else max(4, int(round(360.0 / ring_deg * math.cos(math.radians(el)))))
        for k in range(n):
            dirs.append((360.0 * k / n, el))
    dirs += [(0.0, 90.0), (0.0, -90.0)]
    az, el = np.radians(np.array(dirs)).T
    return np.stack([np.cos(el) * np.cos(az), np.cos(el) * np.sin(az), np.sin(el)], 1)


def sphere_response(cos_theta, f, a):
    """Pressure at the surface point at angle theta from the source, re the free field at the centre."""
    mu = 2 * np.pi * f * a / C
    H = np.zeros((len(cos_theta), len(f)), complex)
    H[:, 0] = 1.0
    m = mu[1:]
    for n in range(int(mu.max()) + 31):
        dh = spherical_jn(n, m, derivative=True) + 1j * spherical_yn(n, m, derivative=True)
        H[:, 1:] += np.outer(eval_legendre(n, -cos_theta), (1j ** (n + 1)) * (2 * n + 1) / dh)
    H[:, 1:] /= m ** 2
    return np.conj(H)  # exp(+i omega t)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--out", required=True)
    ap.add_argument("--rate", type=float, default=44100.0)
    ap.add_argument("--radius", type=float, default=0.09)
    ap.add_argument("--ear-azimuth", type=float, default=100.0)
    ap.add_argument("--ear-elevation", type=float, default=-10.0)
    ap.add_argument("--ring", type=float, default=7.5)
    ap.add_argument("--length", type=int, default=256)
    a = ap.parse_args()
    if not (8000 <= a.rate <= 192000 and 0.03 <= a.radius <= 0.2 and 0 < a.ring <= 90 and a.length >= 64):
        print("ambi_sphere_sofa.py: rate, radius, ring or length out of range", file=sys.stderr)
        sys.exit(2)
    d = grid(a.ring)
    nfft = 4 * a.length
    f = np.arange(nfft // 2 + 1) * a.rate / nfft
    delay = 0.5e-3 + a.radius / C
    fade_f = np.clip((0.5 * a.rate - f) / (0.05 * a.rate), 0.0, 1.0)  # 0.45..0.5 x rate
    ir = np.zeros((len(d), 2, a.length))
    el, az = math.radians(a.ear_elevation), math.radians(a.ear_azimuth)
    for ear, side in enumerate((1.0, -1.0)):  # receiver 0 left (+y)
        e = np.array([math.cos(el) * math.cos(az), side * math.cos(el) * math.sin(az), math.sin(el)])
        H = sphere_response(d @ e, f, a.radius) * np.exp(-2j * np.pi * f * delay) * fade_f
        h = np.fft.irfft(H, nfft, axis=1)[:, :a.length]
        q = a.length // 4
        h[:, -q:] *= 0.5 + 0.5 * np.cos(np.pi * (np.arange(q) + 0.5) / q)
        ir[:, ear, :] = h
    make_sofa.write(a.out, d, a.rate, ir)
    print(f"ambi_sphere_sofa.py: {a.out}: {len(d)} directions ({int(round(360 / a.ring))} horizontal), "
          f"{a.length} taps at {a.rate:g} Hz, sphere {a.radius * 100:g} cm, ears at +-{a.ear_azimuth:g} deg "
          f"azimuth, {a.ear_elevation:g} deg elevation", file=sys.stderr)


if __name__ == "__main__":
    main()

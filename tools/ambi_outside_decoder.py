#!/usr/bin/python3
"""The outside MagLS decoder for tests/bench/ambi_cues.cpp: spaudiopy's.

Runs in a virtual environment with spaudiopy from PyPI (never committed):

    python3 -m venv /tmp/ambi-venv
    /tmp/ambi-venv/bin/pip install spaudiopy==0.2.0 'scipy<1.15'

(spaudiopy 0.2.0 calls scipy.special.sph_harm, which SciPy 1.15 deprecated
and later releases removed.) ambi_cues --outside-python /tmp/ambi-venv/bin/python
runs it; it can also be run by hand:

    ambi_outside_decoder.py --sofa KEMAR.sofa --noise noise.wav \
        --directions directions.csv --orders 1,3,5 --out-dir DIR

For each order N it loads the SOFA file with spaudiopy, resamples the HRIRs
to the noise's rate (resampy, spaudiopy's own resampler), designs
spaudiopy.decoder.magls_bin(hrirs, N) with its defaults, encodes the noise
as a plane wave from each direction with spaudiopy's own real SHs
(spaudiopy.sph.sh_matrix, N3D orthonormal, what its decoder expects) and
decodes it with spaudiopy.decoder.sh2bin. Written to DIR:
  outside_magls_o{N}.wav   stereo float, one segment per direction (in the
                           order of directions.csv), each as long as the noise
  outside_gains_o{N}.csv   azimuth_deg, then spaudiopy's encoding gains
                           converted to ambiX SN3D (for the bench to check
                           its own encoder against)
Nothing of Earshot is used here: the HRIRs, resampling, SHs, design and
convolution are all spaudiopy's (and SciPy's).
"""
import argparse
import csv
import os
import sys


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sofa", required=True)
    ap.add_argument("--noise", required=True, help="mono WAV: the signal to encode")
    ap.add_argument("--directions", required=True, help="CSV with a header and azimuth_deg,elevation_deg rows")
    ap.add_argument("--orders", default="1,3,5")
    ap.add_argument("--out-dir", required=True)
    a = ap.parse_args()

    try:
        import numpy as np
        import soundfile
        import spaudiopy as spa
    except ImportError as e:
        sys.exit(f"ambi_outside_decoder.py: {e} (install spaudiopy into a venv, see the top of this file)")

    noise, fs = soundfile.read(a.noise, dtype="float64")
    if noise.ndim != 1:
        sys.exit(f"{a.noise}: expected one channel")
    dirs = []
    with open(a.directions) as f:
        r = csv.reader(f)
        next(r)
        for row in r:
            dirs.append((float(row[0]), float(row[1])))
    azi = np.deg2rad([d[0] for d in dirs])
    zen = np.pi / 2 - np.deg2rad([d[1] for d in dirs])

    hrirs = spa.io.load_sofa_hrirs(a.sofa)
    if hrirs.fs != fs:
        l, r, _ = spa.process.resample_hrirs(hrirs.left, hrirs.right, hrirs.fs, fs, jobs_count=1)
        hrirs = spa.sig.HRIRs(l, r, hrirs.azi, hrirs.zen, fs)

    os.makedirs(a.out_dir, exist_ok=True)
    n = len(noise)
    for order in [int(o) for o in a.orders.split(",")]:
        dec = spa.decoder.magls_bin(hrirs, order)
        Y = spa.sph.sh_matrix(order, azi, zen, "real")  # (directions, (N+1)^2)
        out = np.zeros((len(dirs) * n, 2))
        for j in range(len(dirs)):
            sig_nm = np.outer(Y[j], noise)
            lr = spa.decoder.sh2bin(sig_nm, dec)
            out[j * n:(j + 1) * n, :] = lr[:, :n].T
        soundfile.write(os.path.join(a.out_dir, f"outside_magls_o{order}.wav"), out.astype(np.float32), fs,
                        subtype="FLOAT")
        degree = np.concatenate([[l] * (2 * l + 1) for l in range(order + 1)])
        sn3d = Y * np.sqrt(4 * np.pi / (2 * degree + 1))
        with open(os.path.join(a.out_dir, f"outside_gains_o{order}.csv"), "w") as f:
            for j, (az, _) in enumerate(dirs):
                f.write(f"{az}," + ",".join(f"{g:.12g}" for g in sn3d[j]) + "\n")
        print(f"ambi_outside_decoder.py: order {order}: {len(dirs)} directions, decoder {dec.shape}", file=sys.stderr)


if __name__ == "__main__":
    main()

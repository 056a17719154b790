#!/usr/bin/env python3
"""Helpers for the `earshot render --ambix` test, standard library only.

  ambix_wav.py write OUT.wav CHANNELS RATE SECONDS AZ_DEG
      a plane wave of noise from azimuth AZ_DEG (ambiX: counter-clockwise,
      90 = left), first order in ACN/SN3D (W, Y, Z, X), the other channels
      silent, 16-bit PCM
  ambix_wav.py ild IN.wav
      prints the broadband level difference left - right in dB of a stereo
      16-bit or float WAV (float: the format earshot render writes)
"""
import math
import random
import struct
import sys
import wave


def write(path, channels, rate, seconds, az_deg):
    rng = random.Random(5)
    az = math.radians(az_deg)
    frames = int(rate * seconds)
    with wave.open(path, "wb") as w:
        w.setnchannels(channels)
        w.setsampwidth(2)
        w.setframerate(rate)
        data = bytearray()
        for _ in range(frames):
            s = rng.uniform(-0.25, 0.25)
            ch = [0.0] * channels
            ch[0] = s
            if channels >= 4:
                ch[1], ch[3] = s * math.sin(az), s * math.cos(az)
            data += struct.pack("<%dh" % channels, *(int(32767 * x) for x in ch))
        w.writeframes(bytes(data))


def read_stereo(path):
    with open(path, "rb") as f:
        b = f.read()
    pos, fmt, bits = 12, None, None
    while pos + 8 <= len(b):
        cid, size = b[pos:pos + 4], struct.unpack_from("<I", b, pos + 4)[0]
        if cid == b"fmt ":
            fmt = struct.unpack_from("<H", b, pos + 8)[0]
            bits = struct.unpack_from("<H", b, pos + 8 + 14)[0]
        elif cid == b"data":
            raw = b[pos + 8:pos + 8 + size]
            if fmt == 3:
                x = struct.unpack("<%df" % (len(raw) // 4), raw)
            else:
                x = [v / 32768 for v in struct.unpack("<%dh" % (len(raw) // 2), raw)]
            return x[0::2], x[1::2]
        pos += 8 + size + (size & 1)
    raise ValueError("no data chunk")


if __name__ == "__main__":
    if sys.argv[1] == "write":
        write(sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), float(sys.argv[5]), float(sys.argv[6]))
    else:
        l, r = read_stereo(sys.argv[2])
        el, er = sum(v * v for v in l[4800:]), sum(v * v for v in r[4800:])
        print("%.2f" % (10 * math.log10(el / er)))

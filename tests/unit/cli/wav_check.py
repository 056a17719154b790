#!/usr/bin/env python3
"""Checks that a WAV file's header is complete: the RIFF size is the file's
size, the data chunk's size is what follows it, a whole number of frames.
Prints the frame count; exits 1 naming the file and the problem otherwise.
(Independent of libsndfile, which wrote it.)"""
import struct
import sys


def frames(path):
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 12 or data[0:4] != b"RIFF" or data[8:12] != b"WAVE":
        raise ValueError("not a RIFF/WAVE file")
    riff_size = struct.unpack_from("<I", data, 4)[0]
    if riff_size != len(data) - 8:
        raise ValueError(f"RIFF size {riff_size} but the file has {len(data) - 8} bytes after it")
    pos, block_align = 12, None
    while pos + 8 <= len(data):
        cid, size = data[pos:pos + 4], struct.unpack_from("<I", data, pos + 4)[0]
        if cid == b"fmt ":
            block_align = struct.unpack_from("<H", data, pos + 8 + 12)[0]
        elif cid == b"data":
            if block_align is None:
                raise ValueError("data chunk before the fmt chunk")
            if pos + 8 + size != len(data):
                raise ValueError(f"data chunk says {size} bytes, the file holds {len(data) - pos - 8}")
            if size % block_align:
                raise ValueError(f"data size {size} is not whole frames of {block_align} bytes")
            return size // block_align
        pos += 8 + size + (size & 1)
    raise ValueError("no data chunk")


if __name__ == "__main__":
    try:
        print(frames(sys.argv[1]))
    except (OSError, ValueError) as e:
        sys.exit(f"{sys.argv[1]}: {e}")

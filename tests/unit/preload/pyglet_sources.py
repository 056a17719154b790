#!/usr/bin/env python3
"""An ordinary pyglet program (pyglet's OpenAL driver, nothing of Earshot's):
a mono noise source 1 m ahead of the listener, played for DURATION seconds.

It sets its listener explicitly and reads it back with alGetListenerfv
(through pyglet's ctypes binding of libopenal) at the start and after the
sound, exiting 3 when OpenAL does not return exactly what it set: under
earshot-openal-run the head turns the effective listener, never the one the
program sees. Prints "readback ok" otherwise.

usage: pyglet_sources.py DURATION_S
"""
import ctypes
import sys
import time

import pyglet

pyglet.options["audio"] = ("openal",)
pyglet.options["shadow_window"] = False  # no display needed

import pyglet.media  # noqa: E402
from pyglet.media.drivers.openal import lib_openal as al  # noqa: E402

POSITION = (0.0, 0.0, 0.0)
ORIENTATION = (0.0, 0.0, -1.0, 0.0, 1.0, 0.0)


def read_back(when):
    pos = (ctypes.c_float * 3)()
    ori = (ctypes.c_float * 6)()
    al.alGetListenerfv(al.AL_POSITION, pos)
    al.alGetListenerfv(al.AL_ORIENTATION, ori)
    if tuple(pos) != POSITION or tuple(ori) != ORIENTATION:
        print(f"readback {when}: position {tuple(pos)} orientation {tuple(ori)}, "
              f"but the program set {POSITION} {ORIENTATION}", file=sys.stderr)
        sys.exit(3)


def main():
    duration = float(sys.argv[1]) if len(sys.argv) > 1 else 2.0
    driver = pyglet.media.get_audio_driver()
    if driver is None or "OpenAL" not in type(driver).__name__:
        sys.exit(f"pyglet_sources.py: pyglet chose {type(driver).__name__}, not OpenAL")
    listener = driver.get_listener()
    listener.position = POSITION
    listener.forward_orientation = ORIENTATION[:3]
    listener.up_orientation = ORIENTATION[3:]
    read_back("at the start")

    noise = pyglet.media.synthesis.WhiteNoise(duration, sample_rate=44100)
    player = pyglet.media.Player()
    player.position = (0.0, 0.0, -1.0)  # 1 m ahead of the listener
    player.min_distance = 1.0
    player.queue(noise)
    player.play()
    end = time.monotonic() + duration
    while time.monotonic() < end:
        pyglet.clock.tick()
        time.sleep(0.02)
    read_back("after playing")
    player.delete()
    print("readback ok")


if __name__ == "__main__":
    main()

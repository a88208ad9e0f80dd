#!/usr/bin/env python3
"""Writes the seeds of fuzz_monitor_datagrams (layout in fuzz_monitor_datagrams.cpp) into corpus/monitor_datagrams:
valid LC02 samples on the default channel, a sample in two LC03 fragments, the liblcm crash pair, a batch.
Run from the repository root: tests/fuzz/make_datagram_seeds.py"""
import os
import struct

OUT = "tests/fuzz/corpus/monitor_datagrams"
# The LCM fingerprint of rockwatch.ground_accel_t as encoded (ground_accel_t::getHash(), big-endian): the first 8
# bytes of every encoded sample (e.g. of corpus/monitor_loop/golden_single_first_1s after its 4-byte header).
FP_ACCEL = bytes.fromhex("865c1b584c500a6c")


def ground_accel(utime, seq, ug):
    # ground_accel_t: fingerprint (8 bytes, big-endian) then fields, as lcm-gen encodes them.
    return FP_ACCEL + struct.pack(">qqiddi", utime, seq, 1, ug, 0.0, 0)


def record(selector, datagram):
    return bytes([selector]) + struct.pack("<H", len(datagram)) + datagram


def lc02(seq, channel, payload):
    return struct.pack(">II", 0x4C433032, seq) + channel + b"\0" + payload


def lc03(seq, size, offset, number, count, body):
    return struct.pack(">IIIIHH", 0x4C433033, seq, size, offset, number, count) + body


def main():
    os.makedirs(OUT, exist_ok=True)
    t0 = 1700000000000000
    samples = b"".join(record(0x04, lc02(i, b"ROCKWATCH_ACCEL", ground_accel(t0 + 5000 * i, i, 0.1 * i))) for i in range(8))
    open(f"{OUT}/samples", "wb").write(b"\x00" + samples)
    p = ground_accel(t0, 0, 1.0)
    frag = record(0x00, lc03(1, len(p), 0, 0, 2, b"ROCKWATCH_ACCEL\0" + p[:20])) + record(
        0x00, lc03(1, len(p), 20, 1, 2, p[20:]))
    open(f"{OUT}/fragmented_sample", "wb").write(b"\x00" + frag)
    crash = record(0x00, lc03(1, 48, 0, 0, 2, b"ROCKWATCH_ACCEL\0" + bytes(20))) + record(
        0x00, lc03(1, 48, 0xFFFFFFF0, 1, 2, bytes(16)))
    open(f"{OUT}/liblcm_crash_pair", "wb").write(b"\x00" + crash)
    short_names = b"".join(record(0x05, lc02(i, b"B", ground_accel(t0 + 5000 * i, i, 0.0))) for i in range(4))
    open(f"{OUT}/short_channel_names", "wb").write(b"\x03" + short_names + record(0x02, lc02(9, b"B", b"")))


if __name__ == "__main__":
    main()

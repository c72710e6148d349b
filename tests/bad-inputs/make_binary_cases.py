#!/usr/bin/env python3
"""Writes the bad-input cases that are binary or that come as a recording's folder:
lapdev/*.lapdev (a device recording, hardware/device_recording.h) and session/*/ (a recorded
session: session.json, and session.lrec as sim/runtime/session_recorder.h lays it out).

    python3 tests/bad-inputs/make_binary_cases.py

Run it after changing a case below and commit what it writes; cases.txt holds the messages.
Each file is built from a valid one with one thing wrong, named for what is wrong."""

import json
import os
import shutil
import struct
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
NAN = float("nan")
INF = float("inf")


def lapdev_header(magic=b"LAPDEV01", version=1, record=112, period=0.001):
    return magic + struct.pack("<IId", version, record, period) + bytes(8)


def lapdev_record(tick, position=(0.0, 0.0, 0.1), gripper=0.5, status=0):
    # int64 tick, double time_s, position[3], orientation w x y z, velocity[3], gripper angle,
    # uint32 buttons, uint32 status: 112 bytes.
    return struct.pack("<q12dII", tick, tick * 0.001, *position, 1.0, 0.0, 0.0, 0.0,
                       0.0, 0.0, 0.0, gripper, 0, status)


def lapdev_cases():
    good = [lapdev_record(i) for i in range(4)]
    body = b"".join(good)
    return {
        "not-a-recording.lapdev": b"this is a text file, not a device recording at all\n",
        "empty.lapdev": b"",
        "version-two.lapdev": lapdev_header(version=2) + body,
        "record-size-100.lapdev": lapdev_header(record=100) + body,
        "period-not-a-number.lapdev": lapdev_header(period=NAN) + body,
        "period-zero.lapdev": lapdev_header(period=0.0) + body,
        "cut-inside-a-record.lapdev": lapdev_header() + body + good[0][:40],
        "ticks-out-of-order.lapdev": lapdev_header() + good[0] + good[1] + lapdev_record(7),
        "nan-position.lapdev": lapdev_header() + good[0] + lapdev_record(1, (0.0, NAN, 0.1)),
        "infinite-gripper.lapdev": lapdev_header() + good[0] + good[1] +
        lapdev_record(2, gripper=INF),
        "unknown-status.lapdev": lapdev_header() + good[0] + lapdev_record(1, status=9),
    }


# A recorded session's folder: its scenario is the shipped default, named relative to the folder
# (tests/bad-inputs/session/CASE/ -> the source tree's scenarios/).
RECORD = {
    "format": "laptrainer-session",
    "version": 1,
    "scenario": "../../../../scenarios/default.yaml",
    "scenario_digest": "0000000000000000",
    "mode": "fast",
    "duration_s": 0.05,
    "haptic_rate_hz": 1000.0,
    "model_rate_hz": 200.0,
    "dominant_hand": "right",
}


def record_text(**changes):
    r = dict(RECORD)
    for k, v in changes.items():
        if v is None:
            del r[k]
        else:
            r[k] = v
    return json.dumps(r, indent=2) + "\n"


def chunk(kind, payload, count=0, first=0, crc_ok=True):
    head = struct.pack("<IIIq", kind, len(payload), count, first)
    crc = zlib.crc32(head + payload) & 0xFFFFFFFF
    return struct.pack("<I", 0x4B43524C) + head + payload + struct.pack(
        "<I", crc if crc_ok else crc ^ 0xFFFF)


def tick_record(tick, position=(0.0, 0.0, 0.1), status=0):
    # int64 tick, int64 wall ns; per tool the sample (12 doubles, uint32 buttons, uint32 status)
    # and what was sent (force[3], squeeze); double gain, uint8 late, uint8 paused, 6 zero bytes.
    out = struct.pack("<qq", tick, 1_700_000_000_000_000_000 + tick * 1_000_000)
    for _ in range(2):
        out += struct.pack("<12dII", tick * 0.001, *position, 1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0,
                           0.5, 0, status)
        out += struct.pack("<4d", 0.0, 0.0, 0.0, 0.0)
    return out + struct.pack("<dBB6x", 1.0, 0, 0)


def tick_record_v3(tick, touch=(0, 0, 0, ())):
    # LAPREC03: the first part as LAPREC01's up to the gain, then uint8 late, paused, resumed,
    # after a hold, tuned, two write statuses, one zero byte; double lateness; int64 the model
    # and surface steps read; per tool its touch: uint8 flags, organs, contacts, one zero byte,
    # and four (uint16 organ, uint16 contacts, float32 force) (sim/runtime/session_recorder.h).
    out = tick_record(tick)[:-8]
    out += struct.pack("<7Bxdqq", 0, 0, 0, 0, 0, 0, 0, 0.0, 0, 0)
    flags, organs, contacts, listed = touch
    out += struct.pack("<3Bx", flags, organs, contacts)
    for k in range(4):
        organ, n, force = listed[k] if k < len(listed) else (0, 0, 0.0)
        out += struct.pack("<HHf", organ, n, force)
    return out + struct.pack("<3Bx", 0, 0, 0) + struct.pack("<HHf", 0, 0, 0.0) * 4


def lrec(header_json, chunks=b"", magic=b"LAPREC01", length=None, crc_ok=True):
    h = header_json.encode()
    crc = zlib.crc32(h) & 0xFFFFFFFF
    return magic + struct.pack("<I", len(h) if length is None else length) + h + struct.pack(
        "<I", crc if crc_ok else crc ^ 1) + chunks


def session_cases():
    """CASE -> {file name: bytes}; a file name ending in / is a folder."""
    head = record_text()
    ticks = b"".join(tick_record(i) for i in range(3))
    cases = {
        # session.json
        "record-not-json": {"session.json": b'{\n  "format": "laptrainer-session",\n'
                                            b'  "version": 1,,\n}\n'},
        "record-a-list": {"session.json": b'[\n  "laptrainer-session", 1\n]\n'},
        "record-other-format": {"session.json": record_text(format="other-program").encode()},
        "record-version-two": {"session.json": record_text(version=2).encode()},
        "record-without-scenario": {"session.json": record_text(scenario=None).encode()},
        "record-scenario-a-number": {"session.json": record_text(scenario=7).encode()},
        "record-digest-not-hex": {"session.json":
                                  record_text(scenario_digest="not-hex-digits!!").encode()},
        "record-mode-slow": {"session.json": record_text(mode="slow").encode()},
        "record-both-hands": {"session.json": record_text(dominant_hand="both").encode()},
        "record-duration-zero": {"session.json": record_text(duration_s=0).encode()},
        "record-rate-too-high": {"session.json": record_text(haptic_rate_hz=1e6).encode()},
        "record-model-faster-than-haptic": {"session.json":
                                            record_text(model_rate_hz=2000.0).encode()},
        "record-scenario-etc-passwd": {"session.json":
                                       record_text(scenario="/etc/passwd").encode()},
        "record-scenario-dots-escape": {"session.json": record_text(
            scenario="../../../../../../../../../../etc/passwd").encode()},
        "record-scenario-nul-byte": {"session.json": record_text(
            scenario="../../../../scenarios/default.yaml\u0000.txt").encode()},
        "record-missing": {"metrics.json": b"{}\n"},
        "record-a-folder": {"session.json/": None, "session.json/README": b"a folder\n"},
        # session.lrec (its session.json is good)
        "recording-not-one": {"session.json": head.encode(),
                              "session.lrec": b"PK\x03\x04 a zip file, not a recording\n"},
        "recording-empty": {"session.json": head.encode(), "session.lrec": b""},
        "recording-header-runs-past-end": {"session.json": head.encode(),
                                           "session.lrec": lrec(head, length=100000)},
        "recording-header-checksum": {"session.json": head.encode(),
                                      "session.lrec": lrec(head, crc_ok=False)},
        "recording-chunk-checksum": {"session.json": head.encode(), "session.lrec": lrec(
            head, chunk(1, ticks, 3, 0, crc_ok=False))},
        "recording-cut-in-first-chunk": {"session.json": head.encode(), "session.lrec": lrec(
            head, chunk(1, ticks, 3, 0)[:100])},
        "recording-nan-in-first-tick": {"session.json": head.encode(), "session.lrec": lrec(
            head, chunk(1, tick_record(0, (NAN, 0.0, 0.1)) + tick_record(1), 2, 0))},
        "recording-unknown-status": {"session.json": head.encode(), "session.lrec": lrec(
            head, chunk(1, tick_record(0, status=12), 1, 0))},
        # a tool on one organ with two contacts, of which the record lists three there
        "recording-impossible-touch": {"session.json": head.encode(), "session.lrec": lrec(
            head, chunk(1, tick_record_v3(0, (0, 1, 2, ((1, 3, 0.5),))), 1, 0),
            magic=b"LAPREC03")},
        "recording-a-folder": {"session.json": head.encode(), "session.lrec/": None,
                               "session.lrec/README": b"a folder\n"},
    }
    return cases


def main():
    lapdev = os.path.join(HERE, "lapdev")
    shutil.rmtree(lapdev, ignore_errors=True)
    os.makedirs(lapdev)
    for name, data in lapdev_cases().items():
        with open(os.path.join(lapdev, name), "wb") as f:
            f.write(data)
    session = os.path.join(HERE, "session")
    shutil.rmtree(session, ignore_errors=True)
    for case, files in session_cases().items():
        folder = os.path.join(session, case)
        os.makedirs(folder)
        for name, data in files.items():
            path = os.path.join(folder, name)
            if name.endswith("/"):
                os.makedirs(path)
                continue
            with open(path, "wb") as f:
                f.write(data if isinstance(data, bytes) else data.encode())


if __name__ == "__main__":
    main()

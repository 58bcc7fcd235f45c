#!/usr/bin/env python3
"""Writes the seed corpora of the libFuzzer targets of tests/fuzz (used by scripts/fuzz.sh).

Usage: make_seeds.py OUT_DIR EXAMPLE_PAIRS_DIR
Creates OUT_DIR/<target>/ for npy_fuzzer, depth_file_fuzzer, pair_directory_fuzzer, sparse_model_fuzzer and
database_blob_fuzzer, shard_file_fuzzer, each with small valid inputs (plus a few near-valid ones). Standard library only.
"""
import json
import os
import struct
import sys


def npy(shape, dtype_descr, payload, fortran=False, version=(1, 0)):
    shape_text = "(" + ", ".join(str(s) for s in shape) + ("," if len(shape) == 1 else "") + ")"
    header = "{'descr': '%s', 'fortran_order': %s, 'shape': %s, }" % (dtype_descr, fortran, shape_text)
    prefix_len = 10 if version[0] == 1 else 12
    total = prefix_len + len(header) + 1
    header += " " * ((64 - total % 64) % 64) + "\n"
    length = struct.pack("<H", len(header)) if version[0] == 1 else struct.pack("<I", len(header))
    return b"\x93NUMPY" + bytes(version) + length + header.encode("latin1") + payload


def floats(fmt, values):
    return struct.pack(fmt[0] + fmt[1] * len(values), *values)


def write(directory, name, data):
    os.makedirs(directory, exist_ok=True)
    with open(os.path.join(directory, name), "wb") as f:
        f.write(data)


def main():
    out, pairs = sys.argv[1], sys.argv[2]
    depth_values = [1.0 + 0.25 * i for i in range(12)]  # 4 x 3

    # ---- npy_fuzzer: real match files of the example pairs (small ones) and synthetic arrays of every kind.
    d = os.path.join(out, "npy_fuzzer")
    for pair in sorted(os.listdir(pairs)):
        pdir = os.path.join(pairs, pair)
        if not os.path.isdir(pdir):
            continue
        for name in sorted(os.listdir(pdir)):
            path = os.path.join(pdir, name)
            if name.endswith(".npy") and os.path.getsize(path) <= 4096:
                with open(path, "rb") as f:
                    write(d, pair + "_" + name, f.read())
    write(d, "f32_2d.npy", npy((4, 3), "<f4", floats("<f", depth_values)))
    write(d, "f64_fortran.npy", npy((3, 4), "<f8", floats("<d", depth_values), fortran=True))
    write(d, "f16_3d.npy", npy((1, 4, 3), "<f2", floats("<e", depth_values)))
    write(d, "be_f8.npy", npy((2, 2), ">f8", floats(">d", [1, 2, 3, 4])))
    write(d, "i64.npy", npy((5,), "<i8", struct.pack("<5q", -2, -1, 0, 1, 2)))
    write(d, "u16.npy", npy((2, 2), "<u2", struct.pack("<4H", 0, 1, 65535, 7)))
    write(d, "bool.npy", npy((3,), "|b1", b"\x00\x01\x01"))
    write(d, "u8.npy", npy((2, 3), "|u1", bytes(range(6))))
    write(d, "scalar.npy", npy((), "<f8", struct.pack("<d", 3.5)))
    write(d, "empty.npy", npy((0, 2), "<f8", b""))
    write(d, "v2.npy", npy((2,), "<f4", floats("<f", [1, 2]), version=(2, 0)))
    write(d, "v3.npy", npy((2,), "<i4", struct.pack("<2i", 1, 2), version=(3, 0)))
    write(d, "complex.npy", npy((1,), "<c16", b"\x00" * 16))

    # ---- depth_file_fuzzer: the same bytes are read as .pfm, .bin and .npy, so seeds of all three formats.
    d = os.path.join(out, "depth_file_fuzzer")
    write(d, "f32.npy", npy((4, 3), "<f4", floats("<f", depth_values)))
    write(d, "f16_chw.npy", npy((1, 4, 3), "<f2", floats("<e", depth_values)))
    write(d, "f64_hwc_fortran.npy", npy((4, 3, 1), "<f8", floats("<d", depth_values), fortran=True))
    write(d, "le.pfm", b"Pf\n3 4\n-1.0\n" + floats("<f", depth_values))
    write(d, "be.pfm", b"Pf\n3 4\n1.0\n" + floats(">f", depth_values))
    write(d, "rgb.pfm", b"PF\n1 1\n-1.0\n" + floats("<f", [1, 2, 3]))
    write(d, "colmap.bin", b"3&4&1&" + floats("<f", depth_values))
    write(d, "colmap3.bin", b"1&1&3&" + floats("<f", [1, 2, 3]))

    # ---- pair_directory_fuzzer: info.json of the example pairs, as they are (their files are not in the fuzzer's
    # directory) and rewritten to name the files the fuzzer provides.
    d = os.path.join(out, "pair_directory_fuzzer")
    for pair in sorted(os.listdir(pairs)):
        path = os.path.join(pairs, pair, "info.json")
        if not os.path.isfile(path):
            continue
        with open(path, "rb") as f:
            raw = f.read()
        write(d, pair + "_original.json", raw)
        info = json.loads(raw)
        info["matches_0_file"], info["matches_1_file"] = "matches_0.npy", "matches_1.npy"
        info["depth_0_file"], info["depth_1_file"] = "depth_0.npy", "depth_1.pfm"
        info["image_size_0"], info["image_size_1"] = [8, 6], [8, 6]
        write(d, pair + "_full.json", json.dumps(info).encode())
        for key in ("depth_0_file", "depth_1_file", "image_size_0", "image_size_1"):
            info.pop(key)
        write(d, pair + "_minimal_png.json", json.dumps(info).encode())  # image0.png only: view 1 must fail
        info["depth_1_file"] = "depth_1.pfm"
        info["T_0to1"] = [row for row in info.get("T_0to1", [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 0]])][:3]
        write(d, pair + "_3x4_depth1.json", json.dumps(info).encode())

    # ---- sparse_model_fuzzer: uint16 sizes of cameras.bin and images.bin, then the three files.
    cameras = struct.pack("<Q", 2)
    cameras += struct.pack("<IiQQ", 1, 1, 640, 480) + floats("<d", [500, 510, 320, 240])  # PINHOLE
    cameras += struct.pack("<IiQQ", 2, 2, 64, 48) + floats("<d", [50, 32, 24, 0.01])  # SIMPLE_RADIAL
    images = struct.pack("<Q", 2)
    for image_id, camera_id, name in ((1, 1, b"a.jpg"), (2, 2, b"dir/b.png")):
        images += struct.pack("<I", image_id) + floats("<d", [1, 0, 0, 0]) + floats("<d", [0.1 * image_id, 0, 0])
        images += struct.pack("<I", camera_id) + name + b"\x00" + struct.pack("<Q", 2)
        images += floats("<d", [10.5, 20.5]) + struct.pack("<Q", 7)
        images += floats("<d", [30.5, 40.5]) + struct.pack("<Q", 2**64 - 1)
    points = struct.pack("<Q", 1) + struct.pack("<Q", 7) + floats("<d", [0.5, -0.25, 3]) + bytes([200, 100, 50])
    points += floats("<d", [0.75]) + struct.pack("<Q", 2) + struct.pack("<IIII", 1, 0, 2, 0)
    d = os.path.join(out, "sparse_model_fuzzer")
    write(d, "two_views", struct.pack("<HH", len(cameras), len(images)) + cameras + images + points)
    empty = struct.pack("<Q", 0)
    write(d, "empty", struct.pack("<HH", 8, 8) + empty * 3)

    # ---- database_blob_fuzzer: 60-byte header, params blob, keypoints blob, matches blob.
    d = os.path.join(out, "database_blob_fuzzer")

    def db_seed(model, params, kp_rows, kp_cols, keypoints, m_rows, m_cols, matches, width=640, height=480):
        header = struct.pack("<iqqiqqqqHH", model, width, height, 1, kp_rows, kp_cols, m_rows, m_cols,
                             len(params), len(keypoints))
        assert len(header) == 60
        return header + params + keypoints + matches

    pinhole = floats("<d", [500, 510, 320, 240])
    kp2 = floats("<f", [1.5, 2.5, 3.5, 4.5, 5.5, 6.5])
    kp6 = floats("<f", [1.5, 2.5, 1, 0, 0, 1, 3.5, 4.5, 1, 0, 0, 1])
    m = struct.pack("<6I", 0, 1, 1, 0, 2, 2)
    write(d, "pinhole_kp2", db_seed(1, pinhole, 3, 2, kp2, 3, 2, m))
    write(d, "simple_radial_kp6", db_seed(2, floats("<d", [500, 320, 240, 0.01]), 2, 6, kp6, 3, 2, m))
    write(d, "empty_rows", db_seed(0, floats("<d", [500, 320, 240]), 0, 6, b"", 0, 2, b""))

    # ---- shard_file_fuzzer: uint16 geometry blob size (0xFFFF: NULL), the geometry blob, the madsfm blob.
    d = os.path.join(out, "shard_file_fuzzer")

    def geometry(flags, config, matches, n_mats, with_q, with_t):
        b = struct.pack("<BiQ", flags, config, len(matches) // 2) + struct.pack("<%dI" % len(matches), *matches)
        b += floats("<d", [0.1 * i for i in range(9 * n_mats)])
        if with_q:
            b += floats("<d", [1, 0, 0, 0])
        if with_t:
            b += floats("<d", [1, 0, 0])
        return b

    madsfm_row = floats("<d", [1, 0, 0, 0, 1, 0, 0, 0, 1, 0.5, 0, 0, 1, 0.1, -0.2, 500, 510, 3.5]) + \
        struct.pack("<7i", 2, 0, 10, 11, 12, 12, 0)

    def shard_seed(geom):
        size = 0xFFFF if geom is None else len(geom)
        return struct.pack("<H", size) + (geom or b"") + madsfm_row

    write(d, "calibrated", shard_seed(geometry(1 | 2 | 8 | 16, 2, [0, 1, 2, 3], 2, True, True)))
    write(d, "uncalibrated", shard_seed(geometry(1 | 8 | 16, 3, [5, 6], 1, True, True)))
    # With COLMAP main's camera2 (flag 64): uint32 size, then COLMAP's camera blob (u32 id, i32 model, u64 width,
    # u64 height, u8 prior, u64 n, n float64).
    camera = struct.pack("<IiQQBQ", 2, 0, 640, 480, 0, 3) + floats("<d", [500, 320, 240])
    write(d, "uncalibrated_camera2",
          shard_seed(geometry(1 | 2 | 8 | 16 | 64, 3, [5, 6], 2, True, True) + struct.pack("<I", len(camera)) + camera))
    write(d, "no_geometry", shard_seed(None))
    write(d, "short_madsfm", struct.pack("<H", 0xFFFF) + madsfm_row[:40])


if __name__ == "__main__":
    main()

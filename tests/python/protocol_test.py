#!/usr/bin/env python3
"""docs/PROTOCOL.md against a real soltexd: brick_client.py, written from the doc alone, fetches
bricks in every codec the server offers and checks each sample against the doc's formulas.

    python3 tests/python/protocol_test.py --soltexd build/server/soltexd
"""
import argparse
import pathlib
import struct
import subprocess
import sys
import tempfile
import time
import unittest

import grpc
import numpy as np

import brick_client as bc

ARGS = None


def start_soltexd(binary, directory):
    """soltexd on loopback port 0; returns the process and its gRPC port."""
    directory = pathlib.Path(directory)
    directory.mkdir(parents=True, exist_ok=True)
    ready = directory / "ready"
    with open(directory / "log", "w") as log:
        process = subprocess.Popen([binary, "--listen", "127.0.0.1:0", "--metrics-listen",
                                    "127.0.0.1:0", "--ready-file", str(ready), "--threads", "2"],
                                   stdout=log, stderr=subprocess.STDOUT)
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        if process.poll() is not None:
            raise RuntimeError(f"soltexd exited with {process.returncode} during start-up:\n"
                               + (directory / "log").read_text())
        lines = ready.read_text().splitlines() if ready.exists() else []
        ports = dict(line.split("=", 1) for line in lines if "=" in line)
        if "grpc" in ports and "metrics" in ports:
            return process, int(ports["grpc"])
        time.sleep(0.02)
    process.kill()
    raise RuntimeError("soltexd did not become ready within 20 s")


def expected_planes(volume, brick_size, level, brick, period=0.75, low=0.1, high=0.7):
    """R, G, B and opacity of the point-sampled colour cube, from PROTOCOL.md and TEXTURES.md."""
    xs, ys, zs = bc.sample_axes(volume, brick_size, level, brick)
    tri = lambda u: np.float32(1 - np.abs(2 * (u - np.floor(u)) - 1))  # double, rounded once
    r = tri(xs / period)[None, None, :]
    g = tri(ys / period)[None, :, None]
    b = tri(zs / period)[:, None, None]
    shape = (brick_size + 1,) * 3
    t = (r + g + b) * (np.float32(1) / np.float32(3))  # float32 throughout
    opacity = np.float32(low) + (np.float32(high) - np.float32(low)) * t
    return np.stack([bc.quantize(np.broadcast_to(c, shape)) for c in (r, g, b, opacity)])


class ProtocolTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.directory = tempfile.TemporaryDirectory(prefix="soltex-protocol-")
        cls.addClassCleanup(cls.directory.cleanup)
        stubs = pathlib.Path(cls.directory.name) / "stubs"
        cls.tx, cls.pb, cls.rpc = bc.load_stubs(ARGS.proto_dir, stubs, ARGS.protoc,
                                                ARGS.grpc_python_plugin)
        process, port = start_soltexd(ARGS.soltexd, cls.directory.name)
        cls.addClassCleanup(process.wait)
        cls.addClassCleanup(process.kill)
        cls.channel = grpc.insecure_channel(f"127.0.0.1:{port}")
        cls.addClassCleanup(cls.channel.close)
        cls.stub = cls.rpc.BrickServiceStub(cls.channel)
        cls.request = bc.colour_cube_request(cls.tx, cls.pb)
        cls.handle = cls.stub.RegisterTexture(cls.request)

    def keys(self):
        # Level 0 brick (2, 1, 3) holds x = 0.1875, where tri(x / 0.75) = 0.5: the rounding tie.
        return [(self.handle.id, 0, 2, 1, 3), (self.handle.id, 1, 1, 0, 1),
                (self.handle.id, 2, 0, 0, 0)]

    def test_handle_describes_the_levels(self):
        self.assertEqual(self.handle.brick_size, 8)
        self.assertEqual(self.handle.finest_level_log2, 5)
        self.assertEqual(self.handle.levels, 3)  # 2^5 cells, bricks of 2^3: levels 0, 1, 2

    def test_every_codec_decodes_to_the_documented_samples(self):
        codecs = list(self.stub.GetServerInfo(self.pb.GetServerInfoRequest()).codecs)
        self.assertCountEqual(codecs, [self.pb.CODEC_RAW, self.pb.CODEC_LZ4, self.pb.CODEC_ZSTD])
        for codec in codecs:
            with self.subTest(codec=self.pb.Codec.Name(codec)):
                bricks, errors = bc.fetch_bricks(self.stub, self.pb, self.keys(), codec)
                self.assertEqual(errors, [])
                self.assertEqual(len(bricks), len(self.keys()))
                for brick in bricks:
                    self.check_brick(brick, codec)

    def check_brick(self, brick, codec):
        self.assertEqual(brick.codec, codec)
        header_codec = brick.payload[7]
        self.assertEqual(header_codec, codec - 1, "header codec id = proto enum - 1")
        decoded = bc.decode_brick(brick.payload)
        self.assertEqual(decoded.checksum, brick.checksum)
        # The 3D predictor before a compressor; raw bricks go without it.
        self.assertEqual(decoded.predictor, 0 if codec == self.pb.CODEC_RAW else 3)
        key = brick.key
        expected = expected_planes(self.request.volume, decoded.size, key.level,
                                   (key.x, key.y, key.z))
        mismatch = np.argwhere(decoded.planes != expected)
        self.assertEqual(len(mismatch), 0,
                         f"level {key.level} brick ({key.x}, {key.y}, {key.z}): "
                         f"{len(mismatch)} samples differ, first [c, z, y, x] = "
                         f"{mismatch[:1].tolist()}")
        if key.level == 0:
            self.assertEqual(decoded.planes[0, 0, 0, 3], 128)  # 0.5 * 255 = 127.5 rounds up

    def test_quantization_edges(self):
        values = [float("nan"), float("-inf"), -0.0, 1e-45, 1 / 255, 0.5, 1.0, 1.0000001,
                  float("inf")]
        self.assertEqual(bc.quantize(values).tolist(), [0, 0, 0, 0, 1, 128, 255, 255, 255])

    def test_first_known_codec_is_taken(self):
        bricks, errors = bc.fetch_bricks(self.stub, self.pb, self.keys()[2:],
                                         [99, self.pb.CODEC_LZ4])
        self.assertEqual(errors, [])
        self.assertEqual([b.codec for b in bricks], [self.pb.CODEC_LZ4])
        bricks, _ = bc.fetch_bricks(self.stub, self.pb, self.keys()[2:], [])
        self.assertEqual([b.codec for b in bricks], [self.pb.CODEC_ZSTD])  # a stream starts on zstd

    def test_bad_keys_get_per_brick_errors(self):
        bricks, errors = bc.fetch_bricks(
            self.stub, self.pb, [(self.handle.id, 3, 0, 0, 0), (self.handle.id, 1, 2, 0, 0),
                                 (self.handle.id ^ 1, 0, 0, 0, 0)], self.pb.CODEC_ZSTD)
        self.assertEqual(bricks, [])
        self.assertEqual(sorted(e.code for e in errors),
                         sorted([grpc.StatusCode.OUT_OF_RANGE.value[0]] * 2 +
                                [grpc.StatusCode.NOT_FOUND.value[0]]))

    def test_a_texture_on_the_stream_needs_no_register_call_there(self):
        # The id is learnt from this server; a second one, which never saw a RegisterTexture,
        # gets the texture in the stream's first message.
        request = bc.colour_cube_request(self.tx, self.pb, period=0.5)
        handle = self.stub.RegisterTexture(request)
        other, port = start_soltexd(ARGS.soltexd, self.directory.name + "/other")
        try:
            with grpc.insecure_channel(f"127.0.0.1:{port}") as channel:
                stub = self.rpc.BrickServiceStub(channel)
                bricks, errors = bc.fetch_bricks(stub, self.pb, [(handle.id, 2, 0, 0, 0)],
                                                 self.pb.CODEC_RAW, textures=[request])
        finally:
            other.kill()
            other.wait()
        self.assertEqual(errors, [])
        decoded = bc.decode_brick(bricks[0].payload)
        np.testing.assert_array_equal(
            decoded.planes, expected_planes(request.volume, 8, 2, (0, 0, 0), period=0.5))

    def test_corrupt_payloads_are_refused(self):
        bricks, _ = bc.fetch_bricks(self.stub, self.pb, self.keys()[:1], self.pb.CODEC_RAW)
        payload = bytearray(bricks[0].payload)
        payload[-1] ^= 1
        with self.assertRaisesRegex(bc.DecodeError, "checksum"):
            bc.decode_brick(bytes(payload))
        with self.assertRaisesRegex(bc.DecodeError, "payload size"):
            bc.decode_brick(bricks[0].payload[:-1])
        bricks, _ = bc.fetch_bricks(self.stub, self.pb, self.keys()[:1], self.pb.CODEC_ZSTD)
        payload = bricks[0].payload + b"junk"
        payload = payload[:16] + struct.pack("<I", len(payload) - 28) + payload[20:]
        with self.assertRaisesRegex(bc.DecodeError, "after the zstd frame"):
            bc.decode_brick(payload)


if __name__ == "__main__":
    parser = argparse.ArgumentParser()
    parser.add_argument("--soltexd", required=True)
    parser.add_argument("--proto-dir", default=str(bc.REPO / "proto"))
    parser.add_argument("--protoc", default="protoc")
    parser.add_argument("--grpc-python-plugin", default="grpc_python_plugin")
    ARGS, rest = parser.parse_known_args()
    unittest.main(argv=[sys.argv[0], *rest], verbosity=2)

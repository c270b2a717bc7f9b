#!/usr/bin/env python3
"""A soltex brick client written from docs/PROTOCOL.md: registers a texture, fetches a brick
and decodes it.

Debian packages: python3-grpcio python3-protobuf python3-numpy python3-lz4 python3-zstandard
python3-xxhash, and protobuf-compiler with protobuf-compiler-grpc to make the Python stubs.

    python3 tests/python/brick_client.py --server 127.0.0.1:7447 [--level 0 --brick 2 1 3]
"""
import argparse
import importlib
import pathlib
import shutil
import struct
import subprocess
import sys
import tempfile
from typing import NamedTuple

import grpc
import lz4.block
import numpy as np
import xxhash
import zstandard

REPO = pathlib.Path(__file__).resolve().parents[2]

# PROTOCOL.md section 7: magic, version, B, C, codec, predictor, reserved, decoded size,
# payload size, checksum.
HEADER = struct.Struct("<4sBBBBB3sIIQ")
CODEC_NAMES = {0: "raw", 1: "lz4", 2: "zstd"}  # header byte 7; the proto enum is one more
# The predictor is undone by running sums along these axes of a [c, z, y, x] array.
PREDICTOR_AXES = {0: (), 1: (3,), 2: (3, 2), 3: (3, 2, 1)}


class DecodeError(ValueError):
    """An encoded brick that is malformed or corrupt."""


class DecodedBrick(NamedTuple):
    size: int  # B
    codec: str
    predictor: int
    checksum: int
    planes: np.ndarray  # uint8, shape (C, B + 1, B + 1, B + 1), indexed [c, z, y, x]


def load_stubs(proto_dir=REPO / "proto", out_dir=None, protoc="protoc",
               plugin="grpc_python_plugin"):
    """Generates the Python modules of proto/soltex/v1 and imports them."""
    out = pathlib.Path(out_dir or tempfile.mkdtemp(prefix="soltex-stubs-"))
    out.mkdir(parents=True, exist_ok=True)
    protos = sorted(str(p) for p in (pathlib.Path(proto_dir) / "soltex" / "v1").glob("*.proto"))
    subprocess.run([protoc, f"-I{proto_dir}", f"--python_out={out}", f"--grpc_python_out={out}",
                    f"--plugin=protoc-gen-grpc_python={shutil.which(plugin) or plugin}", *protos],
                   check=True)
    sys.path.insert(0, str(out))
    return (importlib.import_module("soltex.v1.texture_pb2"),
            importlib.import_module("soltex.v1.brick_service_pb2"),
            importlib.import_module("soltex.v1.brick_service_pb2_grpc"))


def decode_brick(payload: bytes) -> DecodedBrick:
    if len(payload) < HEADER.size:
        raise DecodeError(f"{len(payload)} bytes, shorter than the {HEADER.size}-byte header")
    (magic, version, size, channels, codec, predictor, reserved, decoded_size, payload_size,
     checksum) = HEADER.unpack_from(payload)
    side = size + 1
    for ok, what in [(magic == b"SLTX", "bad magic"), (version == 1, f"version {version}"),
                     (size in (8, 16), f"brick size {size}"),
                     (1 <= channels <= 5, f"{channels} channels"),
                     (codec in CODEC_NAMES, f"codec {codec}"),
                     (predictor in PREDICTOR_AXES, f"predictor {predictor}"),
                     (reserved == b"\0\0\0", "reserved bytes not zero"),
                     (decoded_size == side**3 * channels, f"decoded size {decoded_size}"),
                     (payload_size == len(payload) - HEADER.size, f"payload size {payload_size}")]:
        if not ok:
            raise DecodeError(what)
    body = payload[HEADER.size:]
    if codec == 0:
        raw = body
    elif codec == 1:  # a bare LZ4 block
        raw = lz4.block.decompress(body, uncompressed_size=decoded_size)
    else:  # one zstd frame that declares its size, nothing after it
        if zstandard.get_frame_parameters(body).content_size != decoded_size:
            raise DecodeError("the zstd frame does not declare the decoded size")
        frame = zstandard.ZstdDecompressor().decompressobj()
        raw = frame.decompress(body)
        if frame.unused_data:
            raise DecodeError(f"{len(frame.unused_data)} bytes after the zstd frame")
    if len(raw) != decoded_size:
        raise DecodeError(f"decompressed to {len(raw)} bytes, expected {decoded_size}")
    planes = np.frombuffer(raw, np.uint8).reshape(channels, side, side, side)
    for axis in PREDICTOR_AXES[predictor]:
        planes = np.cumsum(planes, axis=axis, dtype=np.uint8)  # modulo 256
    if xxhash.xxh64_intdigest(planes.tobytes()) != checksum:
        raise DecodeError("checksum mismatch")
    return DecodedBrick(size, CODEC_NAMES[codec], predictor, checksum, planes)


def sample_axes(volume, brick_size, level, brick):
    """The x, y and z coordinates of a brick's samples (PROTOCOL.md section 3), in double."""
    axes = []
    for lo, hi, b in zip((volume.min.x, volume.min.y, volume.min.z),
                         (volume.max.x, volume.max.y, volume.max.z), brick):
        h = (hi - lo) / 2**volume.finest_level_log2 * 2**level
        axes.append(np.array([lo + float(b * brick_size + i) * h
                              for i in range(brick_size + 1)]))
    return axes


def quantize(values) -> np.ndarray:
    """float32 samples to bytes: clamp, then floor(v * 255 + 0.5) with the product in double."""
    v = np.asarray(values, np.float32).astype(np.float64)
    with np.errstate(invalid="ignore"):
        q = np.where(v >= 1, 255.0, np.floor(v * 255 + 0.5))
        return np.where(v > 0, q, 0).astype(np.uint8)  # also NaN -> 0


def fetch_bricks(stub, pb, keys, codec, textures=()):
    """Asks for `keys` ((texture_id, level, x, y, z) tuples) on one stream in one codec;
    returns the bricks and errors the server sent before it ended the stream."""
    request = pb.BrickRequest(
        want=[pb.BrickWant(key=pb.BrickKey(texture_id=t, level=l, x=x, y=y, z=z))
              for t, l, x, y, z in keys],
        accept_codecs=[codec] if isinstance(codec, int) else list(codec),
        textures=list(textures))
    bricks, errors = [], []
    for batch in stub.StreamBricks(iter([request]), timeout=60):
        bricks.extend(batch.bricks)
        errors.extend(batch.errors)
        errors.extend(batch.request_errors)
    return bricks, errors


def colour_cube_request(tx, pb, period=0.75, finest_level_log2=5, brick_size=8):
    """A colour cube with an opacity channel over [-1, 1]^3, sampled at points."""
    return pb.RegisterTextureRequest(
        spec=tx.TextureSpec(colour_cube=tx.ColourCube(period=period),
                            channels=[tx.CHANNEL_OPACITY, tx.CHANNEL_COLOUR],
                            opacity=tx.ScalarRange(low=0.1, high=0.7)),
        volume=tx.Volume(min=tx.Vec3(x=-1, y=-1, z=-1), max=tx.Vec3(x=1, y=1, z=1),
                         finest_level_log2=finest_level_log2),
        brick_size=brick_size, mip_mode=pb.MIP_MODE_POINT)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", default="127.0.0.1:7447")
    parser.add_argument("--level", type=int, default=0)
    parser.add_argument("--brick", type=int, nargs=3, default=(2, 1, 3), metavar=("X", "Y", "Z"))
    args = parser.parse_args()
    tx, pb, rpc = load_stubs()
    with grpc.insecure_channel(args.server) as channel:
        stub = rpc.BrickServiceStub(channel)
        request = colour_cube_request(tx, pb)
        handle = stub.RegisterTexture(request)
        bricks, errors = fetch_bricks(stub, pb, [(handle.id, args.level, *args.brick)],
                                      pb.CODEC_ZSTD)
    if errors or not bricks:
        sys.exit(f"no brick: {errors}")
    brick = decode_brick(bricks[0].payload)
    xs, ys, zs = sample_axes(request.volume, handle.brick_size, args.level, args.brick)
    print(f"texture {handle.id:016x}, brick {tuple(args.brick)} of level {args.level}: "
          f"B = {brick.size}, {brick.planes.shape[0]} planes (R, G, B, opacity), {brick.codec}, "
          f"{len(bricks[0].payload)} bytes, checksum {brick.checksum:016x}")
    for i, j, k in [(0, 0, 0), (3, 0, 0), (brick.size, brick.size, brick.size)]:
        values = ", ".join(f"{q / 255:.3f}" for q in brick.planes[:, k, j, i])
        print(f"  sample ({i}, {j}, {k}) at ({xs[i]}, {ys[j]}, {zs[k]}): {values}")


if __name__ == "__main__":
    main()

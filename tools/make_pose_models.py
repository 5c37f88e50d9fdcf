#!/usr/bin/env python3
"""Dev-only: reproduce the bundled BlazePose ONNX models from the mediapipe 0.10.21 wheel.

Never a run-time dependency. Run it in a separate virtual environment with the converters:

    python -m venv /tmp/posevenv && . /tmp/posevenv/bin/activate
    pip install "tensorflow-cpu>=2.15" tf2onnx onnx onnxruntime numpy   # about 1.3 GB
    python tools/make_pose_models.py --out /tmp/pose_models [--check dip3d_vehicle/models]

Steps (see dip3d_vehicle/models/README.md):
  1. ``pip download`` the mediapipe 0.10.21 cp311 manylinux wheel and unzip the two .tflite files
     (their sha256 is checked);
  2. rewrite the detector's sparse (DENSIFY) weights as dense constants, because tf2onnx cannot
     convert DENSIFY (tensorflow's, or ai-edge-litert's, interpreter computes the dense values);
  3. ``python -m tf2onnx.convert --tflite ... --opset 13``;
  4. store float32 initialisers that float16 represents exactly as float16 behind a Cast;
  5. compare with the bundled files: sha256, and outputs on random input (a different tf2onnx
     version may write different bytes for the same graph).
"""

from __future__ import annotations

import argparse
import hashlib
import subprocess
import sys
import tempfile
import zipfile
from pathlib import Path

import numpy as np

WHEEL = "mediapipe==0.10.21"
WHEEL_ARGS = ["--python-version", "3.11", "--implementation", "cp", "--abi", "cp311",
              "--platform", "manylinux_2_28_x86_64", "--only-binary=:all:"]
SOURCES = {
    "pose_detection": ("mediapipe/modules/pose_detection/pose_detection.tflite",
                       "9ba9dd3d42efaaba86b4ff0122b06f29c4122e756b329d89dca1e297fd8f866c"),
    "pose_landmark_full": ("mediapipe/modules/pose_landmark/pose_landmark_full.tflite",
                           "e9a5c5cb17f736fafd4c2ec1da3b3d331d6edbe8a0d32395855aeb2cdfd64b9f"),
}
OUTPUTS = {"pose_detection": "pose_detection_fp16w.onnx",
           "pose_landmark_full": "pose_landmark_full_fp16w.onnx"}
OPSET = 13
MIN_FP16_SIZE = 64     # smaller initialisers stay float32 (not worth a Cast)


def sha256(path: Path) -> str:
    """Return a file's sha256 hex digest."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def fetch_tflite(work: Path) -> dict[str, Path]:
    """Download the wheel into ``work`` and extract the two .tflite files (sha256 checked)."""
    subprocess.run([sys.executable, "-m", "pip", "download", "--no-deps", WHEEL, *WHEEL_ARGS,
                    "-d", str(work)], check=True)
    wheel = next(work.glob("mediapipe-0.10.21-*.whl"))
    out = {}
    with zipfile.ZipFile(wheel) as zf:
        for name, (member, digest) in SOURCES.items():
            target = work / Path(member).name
            target.write_bytes(zf.read(member))
            if sha256(target) != digest:
                raise SystemExit(f"{member}: sha256 {sha256(target)} differs from {digest}")
            out[name] = target
    return out


def _tflite_api():
    """Return (Interpreter, OpResolverType, schema module, flatbuffer_utils) from tensorflow or litert."""
    try:
        import tensorflow as tf
        from tensorflow.lite.python import schema_py_generated as schema
        from tensorflow.lite.tools import flatbuffer_utils
        return tf.lite.Interpreter, tf.lite.experimental.OpResolverType, schema, flatbuffer_utils
    except ImportError:
        from ai_edge_litert import schema_py_generated as schema
        from ai_edge_litert.interpreter import Interpreter, OpResolverType
        from ai_edge_litert.tools import flatbuffer_utils
        return Interpreter, OpResolverType, schema, flatbuffer_utils


def densify(src: Path, dst: Path) -> int:
    """Write ``src`` to ``dst`` with every DENSIFY op replaced by its dense constant; return the count."""
    interpreter_cls, resolver, schema, fbu = _tflite_api()
    interp = interpreter_cls(model_path=str(src), experimental_preserve_all_tensors=True,
                             experimental_op_resolver_type=resolver.BUILTIN_WITHOUT_DEFAULT_DELEGATES)
    interp.allocate_tensors()
    inp = interp.get_input_details()[0]
    interp.set_tensor(inp["index"], np.zeros(inp["shape"], np.float32))
    interp.invoke()                                  # computes every densified weight once
    model = fbu.read_model(str(src))
    graph = model.subgraphs[0]
    codes = {i for i, code in enumerate(model.operatorCodes)
             if max(code.builtinCode, code.deprecatedBuiltinCode) == schema.BuiltinOperator.DENSIFY}
    kept, count = [], 0
    for op in graph.operators:
        if op.opcodeIndex not in codes:
            kept.append(op)
            continue
        sparse, dense = op.inputs[0], op.outputs[0]
        buffer = schema.BufferT()
        buffer.data = np.frombuffer(interp.get_tensor(dense).tobytes(), np.uint8)
        model.buffers.append(buffer)
        graph.tensors[dense].buffer = len(model.buffers) - 1
        graph.tensors[sparse].sparsity = None
        graph.tensors[sparse].buffer = 0
        count += 1
    graph.operators = kept
    fbu.write_model(model, str(dst))
    return count


def convert(tflite: Path, onnx_path: Path) -> None:
    """Convert a .tflite file to ONNX with tf2onnx."""
    subprocess.run([sys.executable, "-m", "tf2onnx.convert", "--tflite", str(tflite),
                    "--output", str(onnx_path), "--opset", str(OPSET)], check=True)


def store_fp16(src: Path, dst: Path) -> int:
    """Store float32 initialisers exactly representable in float16 as float16 + Cast; return the count."""
    import onnx
    from onnx import TensorProto, helper, numpy_helper

    model = onnx.load(str(src))
    graph = model.graph
    casts = []
    for init in list(graph.initializer):
        arr = numpy_helper.to_array(init)
        if arr.dtype != np.float32 or arr.size < MIN_FP16_SIZE:
            continue
        if not np.array_equal(arr.astype(np.float16).astype(np.float32), arr):
            continue
        half = init.name + "__fp16"
        graph.initializer.remove(init)
        graph.initializer.append(numpy_helper.from_array(arr.astype(np.float16), half))
        casts.append(helper.make_node("Cast", [half], [init.name], to=TensorProto.FLOAT, name=init.name + "__cast"))
    for node in reversed(casts):
        graph.node.insert(0, node)
    onnx.checker.check_model(model)
    onnx.save(model, str(dst))
    return len(casts)


def max_output_difference(a: Path, b: Path, seed: int = 0) -> float:
    """Return the largest absolute difference of two ONNX models' outputs on one random input."""
    import onnxruntime as ort

    sa = ort.InferenceSession(str(a), providers=["CPUExecutionProvider"])
    sb = ort.InferenceSession(str(b), providers=["CPUExecutionProvider"])
    shape = sa.get_inputs()[0].shape
    x = np.random.default_rng(seed).uniform(-1, 1, shape).astype(np.float32)
    name = sa.get_inputs()[0].name
    return max(float(np.abs(p - q).max()) for p, q in zip(sa.run(None, {name: x}), sb.run(None, {name: x})))


def main(argv: list[str] | None = None) -> int:
    """Build both models into --out and compare them with --check (the bundled ones)."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="folder for the .onnx files")
    parser.add_argument("--check", type=Path, default=Path(__file__).resolve().parents[1] / "dip3d_vehicle" / "models",
                        help="folder of the bundled models to compare with")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        tflite = fetch_tflite(work)
        dense = work / "pose_detection_dense.tflite"
        print(f"densified {densify(tflite['pose_detection'], dense)} detector tensors")
        tflite["pose_detection"] = dense
        for name, src in tflite.items():
            raw = work / f"{name}.onnx"
            convert(src, raw)
            out = args.out / OUTPUTS[name]
            print(f"{out.name}: {store_fp16(raw, out)} initialisers as float16")
    for name, file_name in OUTPUTS.items():
        built, bundled = args.out / file_name, args.check / file_name
        same = bundled.is_file() and sha256(built) == sha256(bundled)
        diff = max_output_difference(built, bundled) if bundled.is_file() else float("nan")
        print(f"{file_name}: sha256 {sha256(built)} ({'identical' if same else 'differs'} to bundled; "
              f"max output difference {diff:.3g})")
    return 0


if __name__ == "__main__":
    sys.exit(main())

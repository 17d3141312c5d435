#!/usr/bin/python3
"""Export the ESPNetv2 (PASCAL VOC) segmentation network to ONNX for OpenCV DNN.

Usage (from the repository root):
    /usr/bin/python3 tools/espnetv2/export.py            # the shipped set into models/
    /usr/bin/python3 tools/espnetv2/export.py --only 2.0:384x288 --out /tmp/m

Each model takes a (1,3,H,W) float tensor (RGB, /255, ImageNet mean/std) and returns (1,21,H,W)
class scores (logits). Before writing, every export is checked against the reference frames
(384x384 model only) and the export-friendly graph against the plain PyTorch model.
"""
import argparse
import os
import sys

import numpy as np
import onnx
import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import espnetv2  # noqa: E402
import reference_check  # noqa: E402

REPO = os.path.abspath(os.path.join(os.path.dirname(__file__), "..", ".."))
DEFAULT_WEIGHTS = os.path.abspath(os.path.join(REPO, "..", "shared", "models", "espnetv2"))
# (width multiplier, input width, input height) of the models committed under models/.
SHIPPED = [(2.0, 384, 288), (2.0, 256, 192), (2.0, 384, 384)]
OPSET = 11  # OpenCV 4.6 dnn reads opset 11 Resize (align_corners) and AveragePool


def model_name(s, width, height):
    return f"espnetv2_s{s:.1f}_voc_{width}x{height}.onnx"


def weights_path(folder, s):
    return os.path.join(folder, f"espnetv2_s_{s:.1f}_pascal.pth")


def export(weights_dir, s, width, height, out_path):
    assert width % 32 == 0 and height % 32 == 0, "input size must be divisible by 32"
    plain = espnetv2.load(weights_path(weights_dir, s), s)
    friendly = espnetv2.load(weights_path(weights_dir, s), s, export_friendly=True)
    x = torch.randn(1, 3, height, width, generator=torch.Generator().manual_seed(0))
    with torch.no_grad():
        diff = (plain(x) - friendly(x)).abs().max().item()
    if diff > 1e-3:
        raise RuntimeError(f"export-friendly graph differs from the model by {diff}")
    with torch.no_grad():
        torch.onnx.export(friendly, x, out_path, opset_version=OPSET, input_names=["image"],
                          output_names=["scores"], do_constant_folding=True)
    onnx.checker.check_model(onnx.load(out_path))
    print(f"wrote {out_path} (s={s}, {width}x{height}, {os.path.getsize(out_path) / 1e6:.2f} MB)")
    return friendly


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--weights-dir", default=DEFAULT_WEIGHTS)
    parser.add_argument("--out", default=os.path.join(REPO, "models"))
    parser.add_argument("--only", action="append", help="S:WIDTHxHEIGHT, e.g. 2.0:384x288 (repeatable)")
    parser.add_argument("--no-reference-check", action="store_true")
    args = parser.parse_args()
    todo = SHIPPED
    if args.only:
        todo = []
        for item in args.only:
            s, size = item.split(":")
            w, h = size.split("x")
            todo.append((float(s), int(w), int(h)))
    os.makedirs(args.out, exist_ok=True)
    torch.manual_seed(0)
    for s, w, h in todo:
        model = export(args.weights_dir, s, w, h, os.path.join(args.out, model_name(s, w, h)))
        if (w, h) == (384, 384) and s == 2.0 and not args.no_reference_check:
            agree, close = reference_check.check_model(model, os.path.join(args.weights_dir, "reference"))
            print(f"reference: worst label agreement {100 * agree:.3f}%, person prob within 3 on "
                  f"{100 * close:.3f}%")
            if agree < 0.995 or close < 0.99:
                raise SystemExit("reference check FAILED")
    return 0


if __name__ == "__main__":
    sys.exit(main())

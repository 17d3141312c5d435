"""A caller's labels and masks through the Python module against the folder segmenter.

Usage: PYTHONPATH=build/python /usr/bin/python3 tools/library_inputs_check.py SEQ OUT
SEQ: a sequence from `esdslam synth` (labels/ and masks/ hold the ground truth). Tracks it
single-threaded three times: folder segmenter on labels/ (every frame), the same labels handed in
(label_input), the ground-truth masks handed in (mode geometry); writes OUT/<how>/trajectory.txt
for `esdslam eval SEQ/groundtruth.txt OUT/<how>/trajectory.txt` (docs/RESULTS.md, issue 16).
"""
import os
import sys

import numpy as np
from PIL import Image

import esdslam


def read_list(path):
    return [line.split()[:2] for line in open(path) if line.strip() and not line.startswith("#")]


def run(seq, out, how):
    settings = seq + "/settings.yaml"
    if how == "folder":
        folder_settings = os.path.join(out, "folder.yaml")
        with open(settings) as src, open(folder_settings, "w") as dst:
            dst.write(src.read() + "\nSemantic.segmenter: folder\nSemantic.maskFolder: %s/labels\n" % seq)
        slam = esdslam.System(folder_settings, single_thread=True, out_dir=out + "/folder", segment_every=1)
    elif how == "labels":
        slam = esdslam.System(settings, single_thread=True, out_dir=out + "/labels", label_input=True)
    else:
        slam = esdslam.System(settings, single_thread=True, out_dir=out + "/masks", mode="geometry")
    for (t, rgb), (_, depth) in zip(read_list(seq + "/rgb.txt"), read_list(seq + "/depth.txt")):
        name = os.path.basename(rgb)
        extra = {}
        if how == "labels":
            extra["labels"] = np.asarray(Image.open(seq + "/labels/" + name))
        if how == "masks":
            extra["mask"] = np.ascontiguousarray((np.asarray(Image.open(seq + "/masks/" + name)) > 0).astype(np.uint8) * 255)
        image = np.asarray(Image.open(seq + "/" + rgb).convert("RGB"))
        slam.track(image, np.asarray(Image.open(seq + "/" + depth)).astype(np.uint16), float(t), rgb=True, **extra)
    slam.shutdown()


if __name__ == "__main__":
    os.makedirs(sys.argv[2], exist_ok=True)
    for how in ("folder", "labels", "masks"):
        run(sys.argv[1], sys.argv[2], how)
        print(how, "->", os.path.join(sys.argv[2], how, "trajectory.txt"))

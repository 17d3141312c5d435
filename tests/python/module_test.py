"""The Python module against the CLI (ctest Python.*; label slow).

Usage: module_test.py ESDSLAM_PROGRAM WORK_DIR   (the built module on PYTHONPATH)
A synthetic dynamic sequence through `esdslam run --single-thread` and through
esdslam.System(single_thread=True) gives the same trajectory file; the arrays the module
returns match it; bad input raises with a clear message.
"""
import os
import subprocess
import sys
import tempfile

import numpy as np
from PIL import Image

import esdslam


def read_list(path):
    entries = []
    with open(path) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                t, name = line.split()[:2]
                entries.append((float(t), name))
    return entries


def main(program, work):
    seq = os.path.join(work, "seq")
    subprocess.run([program, "synth", "--preset", "dynamic", "--frames", "60", "--out", seq], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    cli_out = os.path.join(work, "cli")
    subprocess.run([program, "run", "--single-thread", "--settings", seq + "/settings.yaml", "--sequence", seq,
                    "--out", cli_out], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)

    py_out = os.path.join(work, "py")
    slam = esdslam.System(seq + "/settings.yaml", single_thread=True, out_dir=py_out)
    keyframes_seen = []
    slam.set_callbacks(keyframe_added=lambda kf_id, t, pose: keyframes_seen.append(kf_id))
    rgb, depth = read_list(seq + "/rgb.txt"), read_list(seq + "/depth.txt")
    assert len(rgb) == len(depth) == 60
    poses = []
    for (t, rgb_name), (_, depth_name) in zip(rgb, depth):
        image = np.asarray(Image.open(os.path.join(seq, rgb_name)).convert("RGB"))
        raw_depth = np.asarray(Image.open(os.path.join(seq, depth_name))).astype(np.uint16)
        pose = slam.track(image, raw_depth, t, rgb=True)
        assert pose is not None and pose.shape == (4, 4), slam.last_stats
        poses.append(pose)
    assert slam.status == "OK"
    assert slam.last_stats["index"] == 59
    slam.shutdown()

    with open(cli_out + "/trajectory.txt") as a, open(py_out + "/trajectory.txt") as b:
        assert a.read() == b.read(), "trajectories differ"
    stamps, matrices = slam.trajectory()
    assert stamps.shape == (60,) and matrices.shape == (60, 4, 4)
    assert np.allclose(matrices[:, 3, :], [0, 0, 0, 1])
    ids, kf_stamps, kf_poses = slam.keyframes()
    assert len(ids) >= 2 and kf_poses.shape == (len(ids), 4, 4)
    assert len(keyframes_seen) >= len(ids)
    points = slam.map_points()
    assert points.ndim == 2 and points.shape[1] == 3 and len(points) > 100

    try:
        slam.track(np.zeros((10, 10, 3), np.uint8), np.zeros((10, 10), np.float32), 100.0)
        raise AssertionError("track after shutdown did not raise")
    except RuntimeError as e:
        assert "Shutdown" in str(e), e
    try:
        esdslam.System(seq + "/settings.yaml", mode="fast")
        raise AssertionError("a bad mode did not raise")
    except RuntimeError as e:
        assert "none | semantic | geometry | full" in str(e), e
    fresh = esdslam.System(seq + "/settings.yaml", single_thread=True, mode="none")
    try:
        fresh.track(np.zeros((10, 10, 3), np.uint8), np.zeros((10, 10), np.float32), 100.0)
        raise AssertionError("a wrong image size did not raise")
    except RuntimeError as e:
        assert "Camera.width" in str(e), e
    print("python module: 60 frames, trajectory identical to the CLI; %d keyframes, %d map points"
          % (len(ids), len(points)))


if __name__ == "__main__":
    with tempfile.TemporaryDirectory(prefix="esdslam_py_") as work:
        main(sys.argv[1], work)

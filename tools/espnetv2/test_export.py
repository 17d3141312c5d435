#!/usr/bin/python3
"""Tests of the PyTorch port and the ONNX export (run: /usr/bin/python3 tools/espnetv2/test_export.py).

Skipped where torch/onnx or ../shared/models/espnetv2 are absent. There is no ONNX runtime for
Python on the build machine, so the re-export is compared with the committed models node by node
and constant by constant; the C++ slow test (tests/semantic/espnetv2_reference_slow_test.cpp)
compares the outputs of both through OpenCV DNN.
"""
import os
import sys
import tempfile
import unittest

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True

try:
    import onnx
    import torch
    from onnx import numpy_helper
    import espnetv2
    import export
    import reference_check
    HAVE_TORCH = True
except ImportError:  # pragma: no cover
    HAVE_TORCH = False

WEIGHTS = export.DEFAULT_WEIGHTS if HAVE_TORCH else ""


@unittest.skipUnless(HAVE_TORCH and os.path.isdir(WEIGHTS), "needs python3-torch, python3-onnx and ../shared")
class ExportTest(unittest.TestCase):
    def test_every_width_multiplier_loads_strictly(self):
        for s in espnetv2.CHANNELS:
            model = espnetv2.ESPNetv2Seg(s)
            state = torch.load(export.weights_path(WEIGHTS, s), map_location="cpu")
            missing, unexpected = model.load_state_dict(state, strict=True)
            self.assertEqual((list(missing), list(unexpected)), ([], []))
            self.assertEqual(len(model.state_dict()), len(state))

    def test_export_graph_equals_model_on_non_square_input(self):
        plain = espnetv2.load(export.weights_path(WEIGHTS, 1.0), 1.0)
        friendly = espnetv2.load(export.weights_path(WEIGHTS, 1.0), 1.0, export_friendly=True)
        x = torch.randn(1, 3, 192, 256, generator=torch.Generator().manual_seed(1))
        with torch.no_grad():
            self.assertLess((plain(x) - friendly(x)).abs().max().item(), 1e-3)

    def test_reference_frames(self):
        model = espnetv2.load(export.weights_path(WEIGHTS, 2.0), 2.0)
        agree, close = reference_check.check_model(model, os.path.join(WEIGHTS, "reference"), verbose=False)
        self.assertGreaterEqual(agree, 0.995)
        self.assertGreaterEqual(close, 0.99)

    def test_reexport_equals_committed_models(self):
        with tempfile.TemporaryDirectory() as out:
            for s, w, h in export.SHIPPED:
                name = export.model_name(s, w, h)
                committed_path = os.path.join(export.REPO, "models", name)
                self.assertTrue(os.path.isfile(committed_path), committed_path)
                export.export(WEIGHTS, s, w, h, os.path.join(out, name))
                fresh, committed = onnx.load(os.path.join(out, name)), onnx.load(committed_path)
                self.assertEqual([n.op_type for n in fresh.graph.node], [n.op_type for n in committed.graph.node])
                for nf, nc in zip(fresh.graph.node, committed.graph.node):
                    self.assertEqual(nf.op_type, nc.op_type)
                    for af, ac in zip(nf.attribute, nc.attribute):
                        self.assertEqual(af.name, ac.name)
                        if af.type == onnx.AttributeProto.TENSOR:
                            np.testing.assert_allclose(numpy_helper.to_array(af.t), numpy_helper.to_array(ac.t),
                                                       rtol=0, atol=1e-5, err_msg=f"{name}: {nf.name}")
                        else:
                            self.assertEqual(af, ac, f"{name}: {nf.name}")
                a = {t.name: numpy_helper.to_array(t) for t in fresh.graph.initializer}
                b = {t.name: numpy_helper.to_array(t) for t in committed.graph.initializer}
                self.assertEqual(sorted(a), sorted(b))
                for key in a:
                    np.testing.assert_allclose(a[key], b[key], rtol=0, atol=1e-5, err_msg=f"{name}: {key}")


if __name__ == "__main__":
    unittest.main()

"""Compare the PyTorch port with the reference outputs shipped with the weights.

The reference was computed at a 384x384 input (bilinear resize of the whole frame). Criteria:
label maps agree on >= 99.5% of pixels; the person probability (softmax of class 15, 0-255)
is within 3 grey levels on >= 99% of pixels.
"""
import glob
import os

import numpy as np
import torch
from PIL import Image
from torch.nn import functional as F

MEAN = np.array([0.485, 0.456, 0.406], np.float32)
STD = np.array([0.229, 0.224, 0.225], np.float32)
PERSON = 15


def preprocess(rgb_uint8, width, height):
    """HxWx3 uint8 RGB -> (1,3,height,width) tensor. Bilinear resize of the whole frame with
    half-pixel centres, rounded to uint8 (as cv::resize INTER_LINEAR on 8-bit images), /255,
    mean/std."""
    img = torch.from_numpy(rgb_uint8.astype(np.float32)).permute(2, 0, 1)[None]
    img = F.interpolate(img, size=(height, width), mode="bilinear", align_corners=False).round()
    img = img / 255.0
    return (img - torch.from_numpy(MEAN)[None, :, None, None]) / torch.from_numpy(STD)[None, :, None, None]


def compare(scores, ref_labels, ref_person):
    """scores: (21,H,W) numpy. Returns (label agreement, fraction of person prob within 3)."""
    labels = scores.argmax(0)
    e = np.exp(scores - scores.max(0, keepdims=True))
    person = e[PERSON] / e.sum(0) * 255.0
    label_agree = float((labels == ref_labels).mean())
    prob_close = float((np.abs(person - ref_person.astype(np.float32)) <= 3.0).mean())
    return label_agree, prob_close


def reference_frames(folder):
    for path in sorted(glob.glob(os.path.join(folder, "*.labels.png"))):
        stem = path[: -len(".labels.png")]
        rgb = np.array(Image.open(stem + ".png").convert("RGB"))
        labels = np.array(Image.open(path))
        person = np.array(Image.open(stem + ".person_prob.png"))
        yield os.path.basename(stem), rgb, labels, person


def check_model(model, folder, width=384, height=384, verbose=True):
    """Returns the worst (label agreement, person-prob closeness) over the reference frames."""
    worst = (1.0, 1.0)
    with torch.no_grad():
        for name, rgb, labels, person in reference_frames(folder):
            scores = model(preprocess(rgb, width, height))[0].numpy()
            agree, close = compare(scores, labels, person)
            worst = (min(worst[0], agree), min(worst[1], close))
            if verbose:
                print(f"{name}: labels {100 * agree:.3f}%  person prob within 3: {100 * close:.3f}%")
    return worst

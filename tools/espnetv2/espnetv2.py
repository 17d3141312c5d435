"""ESPNetv2 semantic segmentation network (PASCAL VOC, 21 classes), written for ESD-SLAM.

Architecture after Mehta et al., "ESPNetv2" (arXiv:1811.11431) with the segmentation decoder of
the authors' released weights. Module and parameter names follow the shipped state dicts
(see /work/shared/models/espnetv2/state_dict_s2.0.txt), so `load_state_dict(strict=True)` works.

Encoder (strides relative to the input):
  level1    conv3x3/2 + BN + PReLU                                         1/2
  level2_0  strided EESP ++ avg-pool, plus input reinforcement            1/4
  level3_0  same                                                           1/8, then 3 EESP
  level4_0  same                                                           1/16, then 7 EESP
EESP unit: grouped 1x1 reduce -> K=4 depth-wise dilated 3x3 branches fused hierarchically
(each branch adds the previous one) -> BN+PReLU -> grouped 1x1 expand (+ residual) -> PReLU.
Decoder: 4 pyramid-pooling blocks (scales 2, 1.5, 1, 0.5, 0.1) at 1/16, 1/8, 1/4, 1/2, each
fed by x2 bilinear upsampling plus a gated projection of the matching encoder level; finally a
bilinear (align-corners) resize of the 21 class scores to the input size.

`export_friendly=True` replaces the adaptive average poolings (not expressible in ONNX when the
ratio is not an integer) by exact equivalents: integer ratio -> AvgPool, ratio 3:2 -> two
strided poolings interleaved, anything else -> multiplication by constant pooling matrices.
"""
import math

import numpy as np
import torch
from torch import nn
from torch.nn import functional as F

# Channels per level (level1, level2, level3, level4) for each width multiplier s.
CHANNELS = {0.5: (16, 32, 64, 128), 1.0: (32, 64, 128, 256), 2.0: (32, 128, 256, 512)}
BRANCHES = 4
RECEPTIVE_LIMIT = (13, 11, 9, 7)  # largest effective 3x3-dilated kernel per level
EESP_REPEATS = (3, 7)  # plain EESP units after level3_0 and level4_0
PYRAMID_SCALES = (2.0, 1.5, 1.0, 0.5, 0.1)
MIN_POOLED_SIZE = 5
DECODER_BASE = 16
NUM_CLASSES = 21
INPUT_CHANNELS = 3


class ConvBnAct(nn.Module):
    """conv (no bias) -> BN [-> PReLU]; attribute names conv / bn / act as in the state dict."""

    def __init__(self, cin, cout, k, stride=1, groups=1, dilation=1, act=True):
        super().__init__()
        self.conv = nn.Conv2d(cin, cout, k, stride, (k - 1) // 2 * dilation, dilation, groups, bias=False)
        self.bn = nn.BatchNorm2d(cout)
        if act:
            self.act = nn.PReLU(cout)

    def forward(self, x):
        x = self.bn(self.conv(x))
        return self.act(x) if hasattr(self, "act") else x


class BnAct(nn.Module):
    def __init__(self, c):
        super().__init__()
        self.bn = nn.BatchNorm2d(c)
        self.act = nn.PReLU(c)

    def forward(self, x):
        return self.act(self.bn(x))


class DepthwiseDilated(nn.Module):
    def __init__(self, c, stride, dilation):
        super().__init__()
        self.conv = nn.Conv2d(c, c, 3, stride, dilation, dilation, groups=c, bias=False)

    def forward(self, x):
        return self.conv(x)


def branch_dilations(k, limit):
    """Dilation of each EESP branch: effective kernel 3+2i, capped at `limit` (then plain 3x3),
    sorted ascending; a 3x3 kernel with dilation d covers 2d+1 pixels."""
    sizes = sorted(3 + 2 * i if 3 + 2 * i <= limit else 3 for i in range(k))
    return [(s - 1) // 2 for s in sizes]


class EESP(nn.Module):
    def __init__(self, cin, cout, stride, limit, k=BRANCHES):
        super().__init__()
        width = cout // k
        assert width * k == cout
        self.stride = stride
        self.proj_1x1 = ConvBnAct(cin, width, 1, groups=k)
        self.spp_dw = nn.ModuleList(DepthwiseDilated(width, stride, d) for d in branch_dilations(k, limit))
        self.conv_1x1_exp = ConvBnAct(cout, cout, 1, groups=k, act=False)
        self.br_after_cat = BnAct(cout)
        self.module_act = nn.PReLU(cout)  # unused by strided units (the DownSampler activates)

    def forward(self, x):
        reduced = self.proj_1x1(x)
        branches = []
        for conv in self.spp_dw:
            y = conv(reduced)
            branches.append(y if not branches else y + branches[-1])  # hierarchical fusion
        merged = self.conv_1x1_exp(self.br_after_cat(torch.cat(branches, 1)))
        if self.stride == 2:
            return merged
        if merged.shape == x.shape:
            merged = merged + x
        return self.module_act(merged)


class DownSampler(nn.Module):
    """Strided EESP concatenated with a 3x3/2 average pool of the input, plus a projection of
    the (repeatedly pooled) RGB image ("input reinforcement"), then PReLU."""

    def __init__(self, cin, cout, limit):
        super().__init__()
        self.eesp = EESP(cin, cout - cin, 2, limit)
        self.inp_reinf = nn.Sequential(ConvBnAct(INPUT_CHANNELS, INPUT_CHANNELS, 3),
                                       ConvBnAct(INPUT_CHANNELS, cout, 1, act=False))
        self.act = nn.PReLU(cout)
        self.export_friendly = False

    def forward(self, x, image_at_scale):
        pooled = avg_pool_3x3_s2(x, self.export_friendly)
        y = torch.cat([pooled, self.eesp(x)], 1)
        return self.act(y + self.inp_reinf(image_at_scale))


class BaseNet(nn.Module):
    def __init__(self, s):
        super().__init__()
        c1, c2, c3, c4 = CHANNELS[s]
        self.level1 = ConvBnAct(INPUT_CHANNELS, c1, 3, stride=2)
        self.level2_0 = DownSampler(c1, c2, RECEPTIVE_LIMIT[0])
        self.level3_0 = DownSampler(c2, c3, RECEPTIVE_LIMIT[1])
        self.level3 = nn.ModuleList(EESP(c3, c3, 1, RECEPTIVE_LIMIT[2]) for _ in range(EESP_REPEATS[0]))
        self.level4_0 = DownSampler(c3, c4, RECEPTIVE_LIMIT[2])
        self.level4 = nn.ModuleList(EESP(c4, c4, 1, RECEPTIVE_LIMIT[3]) for _ in range(EESP_REPEATS[1]))
        self.export_friendly = False

    def forward(self, image):
        """Returns the features at 1/2, 1/4, 1/8 and 1/16 of the input."""
        images = [image]
        for _ in range(4):  # the image pooled to 1/2 .. 1/16 for input reinforcement
            images.append(avg_pool_3x3_s2(images[-1], self.export_friendly))
        f1 = self.level1(image)
        f2 = self.level2_0(f1, images[2])
        f3 = self.level3_0(f2, images[3])
        for unit in self.level3:
            f3 = unit(f3)
        f4 = self.level4_0(f3, images[4])
        for unit in self.level4:
            f4 = unit(f4)
        return f1, f2, f3, f4


# --- resampling -------------------------------------------------------------------------------

def static_shape(x):
    """Shape as Python ints, so that ONNX export bakes sizes in as constants."""
    return tuple(int(v) for v in x.shape)


class _ResizeAlignCorners(torch.autograd.Function):
    """Bilinear align-corners resize that exports as one ONNX Resize with constant `sizes`
    (the default export computes them from Shape ops, which OpenCV 4.6 cannot import)."""

    @staticmethod
    def forward(ctx, x, height, width):
        return F.interpolate(x, size=(height, width), mode="bilinear", align_corners=True)

    @staticmethod
    def symbolic(g, x, height, width):
        n, c = x.type().sizes()[:2]
        roi = g.op("Constant", value_t=torch.tensor([], dtype=torch.float32))
        scales = g.op("Constant", value_t=torch.tensor([], dtype=torch.float32))
        sizes = g.op("Constant", value_t=torch.tensor([n, c, height, width], dtype=torch.int64))
        return g.op("Resize", x, roi, scales, sizes, coordinate_transformation_mode_s="align_corners",
                    mode_s="linear", nearest_mode_s="floor")


def resize_bilinear(x, size):
    return _ResizeAlignCorners.apply(x, int(size[0]), int(size[1]))


def avg_pool_3x3_s2(x, export_friendly):
    """3x3 average pool, stride 2, zero padding 1 counted in the mean (PyTorch's default). For
    export it is a depth-wise convolution with weights 1/9: the default export adds a dynamic
    Pad subgraph that OpenCV 4.6 cannot import."""
    if not export_friendly:
        return F.avg_pool2d(x, 3, 2, 1)
    c = static_shape(x)[1]
    return F.conv2d(x, torch.from_numpy(np.full((c, 1, 3, 3), 1.0 / 9.0, np.float32)), None, 2, 1, 1, c)


def adaptive_pool_matrix(n_in, n_out):
    """Row i averages inputs [floor(i*n_in/n_out), ceil((i+1)*n_in/n_out)) (PyTorch's rule)."""
    m = np.zeros((n_out, n_in), np.float32)  # numpy: a constant for the exporter, not traced ops
    for i in range(n_out):
        start = (i * n_in) // n_out
        end = -((-(i + 1) * n_in) // n_out)
        m[i, start:end] = 1.0 / (end - start)
    return torch.from_numpy(m)


def pool_axis_3_to_2(x, axis):
    """Adaptive average pooling 3n -> 2n along `axis` (2 = H, 3 = W): output 2j averages inputs
    3j, 3j+1 and output 2j+1 averages 3j+1, 3j+2. Two strided poolings, then interleaved."""
    kernel, stride = ((2, 1), (3, 1)) if axis == 2 else ((1, 2), (1, 3))
    even = F.avg_pool2d(x, kernel, stride, count_include_pad=False)
    odd = F.avg_pool2d(x.narrow(axis, 1, static_shape(x)[axis] - 1), kernel, stride, count_include_pad=False)
    n, c, h, w = static_shape(even)
    if axis == 3:
        both = torch.cat([even.reshape(n, c * h, w, 1), odd.reshape(n, c * h, w, 1)], 3)
        return both.reshape(n, c, h, 2 * w)
    both = torch.cat([even.reshape(n, c * h, 1, w), odd.reshape(n, c * h, 1, w)], 2)
    return both.reshape(n, c, 2 * h, w)


def pool_axis_matrix(x, axis, n_out):
    m = adaptive_pool_matrix(static_shape(x)[axis], n_out).t().contiguous()  # (n_in, n_out)
    if axis == 3:
        return torch.matmul(x, m)
    return torch.matmul(x.transpose(2, 3), m).transpose(2, 3)


def adaptive_pool(x, size, export_friendly):
    if not export_friendly:
        return F.adaptive_avg_pool2d(x, size)
    h, w = static_shape(x)[2:]
    if h % size[0] == 0 and w % size[1] == 0:
        kh, kw = h // size[0], w // size[1]
        return x if kh == kw == 1 else F.avg_pool2d(x, (kh, kw), (kh, kw), count_include_pad=False)
    for axis, n_out in ((3, size[1]), (2, size[0])):
        n_in = static_shape(x)[axis]
        if n_in == n_out:
            continue
        if n_in % n_out == 0:
            k = n_in // n_out
            kernel = (1, k) if axis == 3 else (k, 1)
            x = F.avg_pool2d(x, kernel, kernel, count_include_pad=False)
        elif 2 * n_in == 3 * n_out:
            x = pool_axis_3_to_2(x, axis)
        else:
            x = pool_axis_matrix(x, axis, n_out)
    return x


# --- decoder ----------------------------------------------------------------------------------

class ChannelShuffle(nn.Module):
    """(N, g*c, H, W) -> interleave the g groups channel by channel. 4-D reshapes only."""

    def __init__(self, groups):
        super().__init__()
        self.groups = groups

    def forward(self, x):
        n, c, h, w = static_shape(x)
        y = x.reshape(n, self.groups, c // self.groups, h * w).transpose(1, 2)
        return y.reshape(n, c, h, w)


class SeqConvBnAct(nn.Module):
    """conv -> BN -> PReLU held in a Sequential named `cbr` (decoder naming)."""

    def __init__(self, cin, cout, k, groups=1):
        super().__init__()
        self.cbr = nn.Sequential(nn.Conv2d(cin, cout, k, 1, (k - 1) // 2, groups=groups, bias=False),
                                 nn.BatchNorm2d(cout), nn.PReLU(cout))

    def forward(self, x):
        return self.cbr(x)


class SeqBnAct(nn.Module):
    def __init__(self, c):
        super().__init__()
        self.br = nn.Sequential(nn.BatchNorm2d(c), nn.PReLU(c))

    def forward(self, x):
        return self.br(x)


class PyramidPool(nn.Module):
    """Project to `proj` channels, run a depth-wise 3x3 at 5 scales (resample -> conv ->
    resample back), merge with a grouped 3x3 and a 1x1."""

    def __init__(self, cin, proj, cout, last=False):
        super().__init__()
        self.projection_layer = SeqConvBnAct(cin, proj, 1)
        self.stages = nn.ModuleList(nn.Conv2d(proj, proj, 3, 1, 1, groups=proj, bias=False)
                                    for _ in PYRAMID_SCALES)
        n = len(PYRAMID_SCALES)
        self.merge_layer = nn.Sequential(SeqBnAct(proj * n), ChannelShuffle(n),
                                         SeqConvBnAct(proj * n, proj, 3, groups=proj),
                                         nn.Conv2d(proj, cout, 1, bias=last))
        self.last = last
        if not last:
            self.br = SeqBnAct(cout)
        self.export_friendly = False

    def forward(self, x):
        x = self.projection_layer(x)
        h, w = static_shape(x)[2:]
        outs = []
        for scale, conv in zip(PYRAMID_SCALES, self.stages):
            size = (max(math.ceil(h * scale), MIN_POOLED_SIZE), max(math.ceil(w * scale), MIN_POOLED_SIZE))
            if scale > 1.0:
                y = adaptive_pool(conv(resize_bilinear(x, size)), (h, w), self.export_friendly)
            elif scale < 1.0:
                y = resize_bilinear(conv(adaptive_pool(x, size, self.export_friendly)), (h, w))
            else:
                y = conv(x)
            outs.append(y)
        y = self.merge_layer(torch.cat(outs, 1))
        return y if self.last else self.br(y)


class GatedProjection(nn.Module):
    """Grouped 3x3 conv of an encoder level, scaled per channel by a sigmoid gate computed from
    the level's global average."""

    def __init__(self, cin, cout):
        super().__init__()
        self.wt_layer = nn.Sequential(nn.AdaptiveAvgPool2d(1), nn.Conv2d(cin, cout, 1, bias=False), nn.Sigmoid())
        self.expansion_layer = SeqConvBnAct(cin, cout, 3, groups=math.gcd(cin, cout))

    def forward(self, x):
        return self.expansion_layer(x) * self.wt_layer(x)


class ESPNetv2Seg(nn.Module):
    def __init__(self, s, export_friendly=False):
        super().__init__()
        self.base_net = BaseNet(s)
        c1, c2, c3, c4 = CHANNELS[s]
        dec = (4 * DECODER_BASE, 3 * DECODER_BASE, 2 * DECODER_BASE, NUM_CLASSES)
        proj = min(NUM_CLASSES // 2, DECODER_BASE)
        self.bu_dec_l1 = PyramidPool(c4, proj, dec[0])
        self.bu_dec_l2 = PyramidPool(dec[0], proj, dec[1])
        self.bu_dec_l3 = PyramidPool(dec[1], proj, dec[2])
        self.bu_dec_l4 = PyramidPool(dec[2], proj, dec[3], last=True)
        self.merge_enc_dec_l2 = GatedProjection(c3, dec[0])
        self.merge_enc_dec_l3 = GatedProjection(c2, dec[1])
        self.merge_enc_dec_l4 = GatedProjection(c1, dec[2])
        self.bu_br_l2 = nn.Sequential(nn.BatchNorm2d(dec[0]), nn.PReLU(dec[0]))
        self.bu_br_l3 = nn.Sequential(nn.BatchNorm2d(dec[1]), nn.PReLU(dec[1]))
        self.bu_br_l4 = nn.Sequential(nn.BatchNorm2d(dec[2]), nn.PReLU(dec[2]))
        for m in self.modules():
            if hasattr(m, "export_friendly"):
                m.export_friendly = export_friendly

    def forward(self, image):
        """image: (1, 3, H, W) normalised RGB, H and W divisible by 32 -> (1, 21, H, W) scores."""
        f1, f2, f3, f4 = self.base_net(image)
        y = self.bu_dec_l1(f4)
        for skip, gate, br, block in ((f3, self.merge_enc_dec_l2, self.bu_br_l2, self.bu_dec_l2),
                                      (f2, self.merge_enc_dec_l3, self.bu_br_l3, self.bu_dec_l3),
                                      (f1, self.merge_enc_dec_l4, self.bu_br_l4, self.bu_dec_l4)):
            y = resize_bilinear(y, static_shape(skip)[2:])  # x2
            y = block(br(y + gate(skip)))
        return resize_bilinear(y, static_shape(image)[2:])


def load(path, s, export_friendly=False):
    model = ESPNetv2Seg(s, export_friendly)
    state = torch.load(path, map_location="cpu")
    model.load_state_dict(state, strict=True)
    return model.eval()

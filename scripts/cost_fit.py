"""The cost model's terms fitted to measured frames, for scripts/fit-profile
(the profile) and scripts/bench-corpus (the block limit): each frame's
features (`depthcull bench --json`'s model_features) as a row of the
least-squares problem, and non-negative least squares on the relative
error. Pure Python, so the scripts need no numpy."""

TERMS = ["frame_us", "clear_color_ns_per_pixel", "clear_depth_ns_per_pixel", "draw_call_us", "texture_switch_us",
         "triangle_us", "triangle_perimeter_ns_per_pixel", "fragment_opaque_ns", "fragment_blend_ns", "fragment_rejected_ns"]


# The block model (docs/ideal-frame.md section 9): llvmpipe shades whole
# 4x4 blocks, so the fragment and perimeter terms are replaced by the
# blocks each pass's triangles cover (model_features opaque_blocks,
# blend_blocks). A profile cannot price blocks yet: fit-profile --blocks
# prints this fit's terms and error beside the profile fit's, to compare,
# and bench-corpus prices the ideal frame with it (the block limit).
SHARED = 6  # frame .. triangle_us: the terms both models have, first in TERMS and row()
BLOCK_TERMS = TERMS[:SHARED] + ["opaque_block_ns", "blend_block_ns", "fragment_rejected_ns"]


def block_row(f):
    return row(f)[:SHARED] + [f["opaque_blocks"] * 1e-6, f["blend_blocks"] * 1e-6, f["rejected_fragments"] * 1e-6]


def predict(r, terms):
    """A row's frame time (ms) by fitted terms."""
    return sum(a * c for a, c in zip(r, terms))


def fit(rows, y):
    """NNLS on the relative error; returns the terms and each frame's |error|."""
    b = nnls(rows, y, [1 / max(v, 0.05) for v in y])
    return b, [abs(predict(r, b) - v) / v for r, v in zip(rows, y)]


def row(f):
    px = f["pixels"] * 1e-6
    return [1e-3, px, px if f["depth_clear"] else 0.0, f["draw_calls"] * 1e-3, f["texture_switches"] * 1e-3,
            f["triangles"] * 1e-3, f["triangle_perimeter"] * 1e-6, f["opaque_fragments"] * 1e-6,
            f["blend_fragments"] * 1e-6, f["rejected_fragments"] * 1e-6]


def solve(a, b):
    n = len(a)
    m = [r[:] + [v] for r, v in zip(a, b)]
    for i in range(n):
        p = max(range(i, n), key=lambda r: abs(m[r][i]))
        m[i], m[p] = m[p], m[i]
        if abs(m[i][i]) < 1e-18:
            return None
        for r in range(n):
            if r != i:
                f = m[r][i] / m[i][i]
                for c in range(i, n + 1):
                    m[r][c] -= f * m[i][c]
    return [m[i][n] / m[i][i] for i in range(n)]


def nnls(x, y, w):
    """Least squares, dropping the most negative term until none is negative."""
    cols = list(range(len(x[0])))
    while cols:
        a = [[sum(w[k] ** 2 * x[k][i] * x[k][j] for k in range(len(x))) for j in cols] for i in cols]
        b = [sum(w[k] ** 2 * x[k][i] * y[k] for k in range(len(x))) for i in cols]
        s = solve(a, b)
        if s is None:
            cols.pop()
            continue
        if min(s) >= 0:
            out = [0.0] * len(x[0])
            for c, v in zip(cols, s):
                out[c] = v
            return out
        cols.remove(min(zip(s, cols))[1])
    return [0.0] * len(x[0])

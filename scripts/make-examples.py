#!/usr/bin/env python3
"""Generates the bundled example art and scene in examples/ (made by us,
deterministic, standard library only). Re-run to regenerate:

    python3 scripts/make-examples.py
"""
import json, math, os, random, struct, zlib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples")


def write_png(path, w, h, pixels):
    """pixels: list of (r, g, b, a) rows, row-major."""
    raw = bytearray()
    for y in range(h):
        raw.append(0)
        for x in range(w):
            raw.extend(pixels[y * w + x])
    def chunk(tag, data):
        c = struct.pack(">I", len(data)) + tag + data
        return c + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(bytes(raw), 9)) + chunk(b"IEND", b"")
    with open(path, "wb") as f:
        f.write(png)


def clamp(v):
    return max(0, min(255, int(round(v))))


def image(w, h, fn):
    return w, h, [fn(x + 0.5, y + 0.5) for y in range(h) for x in range(w)]


def coverage(d):
    """Signed distance (negative inside) -> alpha: opaque inside, a 1.5 texel soft rim."""
    if d <= -0.75:
        return 255
    if d >= 0.75:
        return 0
    return clamp(255 * (0.75 - d) / 1.5)


rng = random.Random(20261121)
noise = [rng.random() for _ in range(4096)]


def n(x, y):
    return noise[(int(x) * 73 + int(y) * 151) % 4096]


def grass(x, y):
    k = n(x, y)
    return (clamp(60 + 30 * k), clamp(140 + 50 * k), clamp(50 + 20 * k), 255)


def dirt(x, y):
    k = n(x, y)
    return (clamp(130 + 40 * k), clamp(95 + 30 * k), clamp(60 + 20 * k), 255)


def rock(x, y):
    cx, cy = 24, 21
    d = math.hypot((x - cx) / 1.15, (y - cy)) - 16 + 2.5 * math.sin(3 * math.atan2(y - cy, x - cx))
    k = n(x, y)
    return (clamp(120 + 40 * k - (y - cy)), clamp(120 + 35 * k - (y - cy)), clamp(125 + 30 * k), coverage(d))


def tree(x, y):
    canopy = math.hypot(x - 32, y - 34) - 27 + 2 * math.sin(7 * math.atan2(y - 34, x - 32))
    trunk = max(abs(x - 32) - 6, abs(y - 78) - 17)
    if canopy < trunk:
        k = n(x, y)
        return (clamp(30 + 30 * k), clamp(110 + 60 * k - 0.5 * y), clamp(40 + 20 * k), coverage(canopy))
    return (110, 75, 40, coverage(trunk))


def bush(x, y):
    d = min(math.hypot(x - 13, y - 16) - 11, math.hypot(x - 27, y - 14) - 12.5)
    k = n(x, y)
    return (clamp(40 + 30 * k), clamp(120 + 50 * k), clamp(50 + 10 * k), coverage(d))


def flower(x, y):
    d = math.hypot(x - 6, y - 6)
    petal = d - (4.5 + 1.2 * math.cos(5 * math.atan2(y - 6, x - 6)))
    if d < 1.8:
        return (250, 210, 40, 255)
    return (235, 90, 150, coverage(petal))


def moons(x, y):
    # two disjoint parts: a disc and a crescent
    disc = math.hypot(x - 11, y - 12) - 9
    crescent = max(math.hypot(x - 36, y - 12) - 10, -(math.hypot(x - 40, y - 10) - 7))
    d = min(disc, crescent)
    return (230, 230, 190, coverage(d))


def ring(x, y):
    r = math.hypot(x - 24, y - 24)
    d = max(r - 22, 12 - r)
    return (200, 160, 60, coverage(d))


def glow(x, y):
    r = math.hypot(x - 16, y - 16) / 16
    a = 0 if r >= 1 else clamp(200 * (1 - r) ** 2)
    return (255, 230, 150, a)


def shadow(x, y):
    d = math.hypot((x - 24) / 24, (y - 8) / 8)
    a = 0 if d >= 1 else clamp(110 * (1 - d ** 2))
    return (40, 40, 60, a)


SPRITES = {
    "grass": image(32, 32, grass),
    "dirt": image(32, 32, dirt),
    "rock": image(48, 40, rock),
    "tree": image(64, 96, tree),
    "bush": image(40, 28, bush),
    "flower": image(12, 12, flower),
    "moons": image(48, 24, moons),
    "ring": image(48, 48, ring),
    "glow": image(32, 32, glow),
    "shadow": image(48, 16, shadow),
}


def affine(tx, ty, angle=0.0, sx=1.0, sy=1.0, w=0, h=0):
    """Rotate/scale about the sprite centre, then place its centre at (tx, ty)."""
    c, s = math.cos(math.radians(angle)), math.sin(math.radians(angle))
    a, b, cc, d = c * sx, s * sx, -s * sy, c * sy
    e = tx - (a * w / 2 + cc * h / 2)
    f = ty - (b * w / 2 + d * h / 2)
    return [round(v, 6) for v in (a, b, cc, d, e, f)]


def main():
    os.makedirs(os.path.join(ROOT, "art"), exist_ok=True)
    for name, (w, h, px) in SPRITES.items():
        write_png(os.path.join(ROOT, "art", name + ".png"), w, h, px)

    W, H = 640, 480
    elements = []
    # Ground: opaque tiles, a dirt path winding through grass.
    for ty in range(H // 32):
        for tx in range(W // 32):
            on_path = abs(tx - (10 + 4 * math.sin(ty / 2.5))) < 1.2
            elements.append({"image": "dirt" if on_path else "grass", "transform": [1, 0, 0, 1, tx * 32, ty * 32]})
    # Props, back to front by y so nearer things overlap farther ones.
    props = []
    for _ in range(40):
        props.append(("flower", rng.uniform(0, W), rng.uniform(0, H), rng.uniform(0, 360), rng.uniform(0.8, 1.6)))
    for _ in range(14):
        props.append(("rock", rng.uniform(0, W), rng.uniform(0, H), rng.uniform(-30, 30), rng.uniform(0.7, 1.5)))
    for _ in range(12):
        props.append(("bush", rng.uniform(0, W), rng.uniform(0, H), 0, rng.uniform(0.9, 1.4)))
    for _ in range(6):
        props.append(("ring", rng.uniform(0, W), rng.uniform(0, H), rng.uniform(0, 90), 1.0))
    for _ in range(4):
        props.append(("moons", rng.uniform(0, W), rng.uniform(0, H), rng.uniform(-20, 20), 1.2))
    for _ in range(16):
        props.append(("tree", rng.uniform(0, W), rng.uniform(0, H), rng.uniform(-6, 6), rng.uniform(0.8, 1.3)))
    props.sort(key=lambda p: (p[2], p[1]))
    for i, (name, x, y, angle, scale) in enumerate(props):
        w, h, _ = SPRITES[name]
        if name in ("tree", "rock", "bush"):
            sw, sh, _ = SPRITES["shadow"]
            elements.append({"image": "shadow", "transform": affine(x + 4, y + h * scale / 2 - 4, 0, scale * w / sw, scale, sw, sh),
                             "blend": "multiply"})
        flip = -1 if (name == "tree" and i % 3 == 0) else 1
        el = {"image": name, "transform": affine(x, y, angle, scale * flip, scale, w, h)}
        if name == "rock" and i % 4 == 0:
            el["color"] = [0.85, 0.8, 1.0, 1.0]
        if name == "tree" and i % 5 == 0:
            el["color"] = [1.0, 1.0, 1.0, 0.75]
        elements.append(el)
    # Fireflies: additive glows on top.
    for _ in range(25):
        elements.append({"image": "glow", "transform": affine(rng.uniform(0, W), rng.uniform(0, H), 0, rng.uniform(0.5, 1.5),
                                                              rng.uniform(0.5, 1.5), 32, 32), "blend": "add",
                         "color": [1.0, 0.95, 0.7, 0.8]})

    scene = {
        "viewport": {"width": W, "height": H},
        "images": [{"id": name, "path": "art/%s.png" % name} for name in SPRITES],
        "elements": elements,
    }
    with open(os.path.join(ROOT, "meadow.json"), "w") as f:
        json.dump(scene, f, indent=1)
        f.write("\n")
    print("examples: %d images, %d elements" % (len(SPRITES), len(elements)))


if __name__ == "__main__":
    main()

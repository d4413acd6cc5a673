#!/usr/bin/env python3
"""Writes the cages with narrow places used by the graded-sampling tests and `bench --graded`:
each drawn tightly (the narrow version) and with its gaps widened to 40 px (the wide version)."""
import json, math, os

HERE = os.path.dirname(os.path.abspath(__file__))


def person(arm_gap, leg_gap):
    # Torso x in [160, 240]; arms hang beside it arm_gap px away; legs leg_gap px apart.
    cx = 200.0
    half_leg = leg_gap / 2.0
    right = [(215, 100), (240, 110), (240 + arm_gap + 28, 115), (240 + arm_gap + 28, 280), (240 + arm_gap + 14, 292),
             (240 + arm_gap, 280), (240 + arm_gap, 130), (240, 136), (240, 300), (cx + half_leg + 38, 480),
             (cx + half_leg + 4, 480), (cx + half_leg, 470), (cx + half_leg, 322)]
    left = [(2 * cx - x, y) for (x, y) in reversed(right)]
    head = [(170, 72), (178, 40), (200, 28), (222, 40), (230, 72)]
    pts = right + left + head
    shift = max(0.0, arm_gap + 28 + 40 - 160)  # keep the left arm inside the picture
    pts = [(x + shift, y) for (x, y) in pts]
    return pts, (int(400 + 2 * shift), 520)


def slit(width):
    a, b = 150 - width / 2.0, 150 + width / 2.0
    return [(50, 50), (a, 50), (a, 200), (b, 200), (b, 50), (250, 50), (250, 250), (50, 250)], (300, 300)


def blob_neck(width):
    # Two discs of radius 60 (16 points each) joined by a neck `width` px wide and about 20 px long.
    n = 16
    half = width / 2.0
    # Left blob from its neck's lower joint round to the upper one (y down), then the neck, the right blob.
    lx, rx = 90.0 + 60.0 * math.cos(math.asin(half / 60.0)), 230.0 - 60.0 * math.cos(math.asin(half / 60.0))
    out = [(lx, 120 + half)]
    for k in range(1, n):
        t = 2 * math.pi * k / n
        x, y = 90 + 60 * math.cos(t), 120 + 60 * math.sin(t)
        if abs(y - 120) > half + 1.0 or x < 140:
            out.append((x, y))
    out.append((lx, 120 - half))
    out.append((rx, 120 - half))
    for k in range(1, n):
        t = math.pi + 2 * math.pi * k / n
        x, y = 230 + 60 * math.cos(t), 120 + 60 * math.sin(t)
        if abs(y - 120) > half + 1.0 or x > 180:
            out.append((x, y))
    out.append((rx, 120 + half))
    return out, (320, 240)


def armpit(gap):
    # A torso x in [100, 180] and an arm beside it: drawn tightly (gap 0) the arm's inner wall meets the
    # torso's at the armpit (180, 100), a wedge of 2.9 degrees that is 10 px wide at the hand; widened,
    # the arm hangs `gap` px away with a flat armpit.
    if gap == 0:
        return [(100, 40), (230, 40), (226, 300), (190, 300), (180, 100), (180, 320), (100, 320)], (320, 360)
    return [(100, 40), (230 + gap, 40), (226 + gap, 300), (190 + gap, 300), (180 + gap, 100), (180, 100), (180, 320),
            (100, 320)], (320 + gap, 360)


def write(name, pts, size):
    with open(os.path.join(HERE, name + ".cage.json"), "w") as f:
        json.dump({"version": 1, "points": [[round(x, 3), round(y, 3)] for x, y in pts], "closed": True,
                   "image_size": list(size)}, f)
        f.write("\n")


for tag, (a, l, s, n) in {"narrow": (6, 4, 3, 2), "wide": (40, 40, 40, 40)}.items():
    write("person-" + tag, *person(a, l))
    write("slit-" + tag, *slit(s))
    write("neck-" + tag, *blob_neck(n))
    write("armpit-" + tag, *armpit(0 if tag == "narrow" else 40))

#!/usr/bin/env python3
"""Measure face-box detection per photo set for several cascades and settings, to choose the
detect.* defaults (docs/detect-cascades.md). Uses bench/cascade_detect (our evaluator, whose boxes
equal OpenCV's) with --neighbors-list, so each (cascade, scale, min size) is scanned once.

Use: cascade_defaults.py TOOL OUTDIR [--quick]
A photo's face counts as found when a box's centre lies inside its known region and the box side
is 0.5-2x the region's (mean) side. Regions: LFW thumbnails, the centred ~60 px face; landmark sets,
the bounding box of each .pts; video frames, the central 60% of the frame. Nonface_* photos and
extra boxes on the one-person video frames count as false positives.
"""
import glob, json, os, re, subprocess, sys

PHOTOS = os.environ.get("FRIG_PHOTOS", os.path.join(os.path.dirname(__file__), "..", "..", "shared", "photos"))
CASCADES = {
    "haar_alt2": "haarcascades/haarcascade_frontalface_alt2.xml",
    "haar_alt": "haarcascades/haarcascade_frontalface_alt.xml",
    "haar_default": "haarcascades/haarcascade_frontalface_default.xml",
    "haar_alt_tree": "haarcascades/haarcascade_frontalface_alt_tree.xml",
    "lbp_frontal": "lbpcascades/lbpcascade_frontalface.xml",
    "lbp_improved": "lbpcascades/lbpcascade_frontalface_improved.xml",
    "haar_profile": "haarcascades/haarcascade_profileface.xml",
    "haar_profile_flip": "haarcascades/haarcascade_profileface.xml",  # run on the mirrored photo
}
NEIGHBORS = [1, 2, 3, 4, 5, 6]


def read_pts(path):
    nums = re.findall(r"[-+0-9.eE]+", open(path).read().split("{")[1].split("}")[0])
    xs, ys = [float(v) - 1 for v in nums[0::2]], [float(v) - 1 for v in nums[1::2]]
    return (min(xs), min(ys), max(xs) - min(xs), max(ys) - min(ys))


def regions(path, w, h):
    """Known faces of a photo (list of x, y, w, h), or None when unknown."""
    folder, stem = os.path.basename(os.path.dirname(path)), os.path.splitext(path)[0]
    if folder.startswith("lfw"):
        return [(45, 45, 60, 60)]
    if folder.startswith("video"):
        return [(0.2 * w, 0.2 * h, 0.6 * w, 0.6 * h)]
    if os.path.basename(stem).startswith("nonface"):
        return []
    pts = sorted(glob.glob(stem + ".pts") + glob.glob(stem + "_face[0-9][0-9].pts"))
    return [read_pts(p) for p in pts] if pts else None


def hit(box, reg):
    cx, cy = box[0] + box[2] / 2, box[1] + box[3] / 2
    side, rside = (box[2] * box[3]) ** 0.5, (reg[2] * reg[3]) ** 0.5
    return reg[0] <= cx <= reg[0] + reg[2] and reg[1] <= cy <= reg[1] + reg[3] and 0.5 <= side / rside <= 2


def group_of(path):
    folder = os.path.basename(os.path.dirname(path))
    if folder.startswith("lfw"):
        return "lfw"
    if folder.startswith("video"):
        return "video"
    if folder.startswith("bing"):
        return "bing"
    if folder.startswith("landmarks_300w"):
        return "300w"
    if folder.startswith("landmarks_dlib"):
        return "dlib_faces"
    return "outliers"


def run(tool, name, scale, min_size, files, out):
    if not os.path.exists(out):
        cmd = [tool, "--cascade", "/usr/share/opencv4/" + CASCADES[name], "--scale", str(scale), "--min-size",
               str(min_size), "--neighbors-list", ",".join(map(str, NEIGHBORS)), "--flip", str(int("flip" in name))]
        cmd += files
        res = subprocess.run(cmd, capture_output=True, text=True, check=True)
        open(out + ".tmp", "w").write(res.stdout)
        os.replace(out + ".tmp", out)
    return [json.loads(line) for line in open(out)]


def score(results, k, sizes):
    s = {g: [0, 0] for g in ("lfw", "video", "300w", "dlib_faces", "hardpose")}
    fp_video = fp_nonface = bing_any = bing_n = bing_boxes = seconds = 0
    for r in results:
        path, boxes = r["image"], r["by_neighbors"][str(k)]
        seconds += r["seconds"]
        g = group_of(path)
        if g == "bing":
            bing_n += 1
            bing_any += bool(boxes)
            bing_boxes += len(boxes)
            continue
        regs = regions(path, *sizes[path])
        if regs is None:
            continue
        if os.path.basename(path).startswith("nonface"):
            fp_nonface += len(boxes)
            continue
        key = "hardpose" if os.path.basename(path).startswith("hardpose") else g
        for reg in regs:
            s[key][1] += 1
            s[key][0] += any(hit(b, reg) for b in boxes)
        if g == "video":
            fp_video += sum(not hit(b, regs[0]) for b in boxes)
    return s, fp_video, fp_nonface, bing_any, bing_n, bing_boxes, seconds


def main():
    tool, outdir = sys.argv[1], sys.argv[2]
    quick = "--quick" in sys.argv
    os.makedirs(outdir, exist_ok=True)
    files = sorted(glob.glob(os.path.join(PHOTOS, "*", "*.jpg")) + glob.glob(os.path.join(PHOTOS, "*", "*.png")))
    sizes = {}
    for f in files:  # image sizes from the tool's own reader would be slower; read headers here
        sizes[f] = image_size(f)
    configs = [(c, 1.1, 30) for c in CASCADES]  # the profile cascade also mirrored
    if not quick:
        # the frontal cascades that did best at 1.1/30 (alt2, default; alt is alt2's older twin) are
        # explored further: pyramid step, then smallest face
        configs += [(c, sf, 30) for c in ("haar_alt2", "haar_alt", "haar_default") for sf in (1.05, 1.2)]
        configs += [(c, 1.1, m) for c in ("haar_alt2", "haar_default") for m in (20, 40)]
    print("cascade        scale min k | lfw%   video%  300w   dlib   hardpose | FP video FP nonface | bing>=1  boxes/img | s/img")
    for name, sf, m in configs:
        res = run(tool, name, sf, m, files, os.path.join(outdir, f"{name}_{sf}_{m}.jsonl"))
        for k in NEIGHBORS:
            s, fpv, fpn, ba, bn, bb, sec = score(res, k, sizes)
            pct = lambda g: 100.0 * s[g][0] / max(s[g][1], 1)
            print(f"{name:14s} {sf:4.2f} {m:3d} {k} | {pct('lfw'):5.1f} {pct('video'):6.1f} "
                  f"{s['300w'][0]:2d}/{s['300w'][1]:2d} {s['dlib_faces'][0]:2d}/{s['dlib_faces'][1]:2d} "
                  f"{s['hardpose'][0]}/{s['hardpose'][1]}      | {fpv:8d} {fpn:10d} | {100.0 * ba / max(bn, 1):6.1f}% "
                  f"{bb / max(bn, 1):9.2f} | {sec / len(res):.3f}")
        sys.stdout.flush()
    union(outdir, sizes)


def union(outdir, sizes):
    """The frontal cascade alone and with the profile cascade (as is, and on the mirrored photo)."""
    load = lambda name: {r["image"]: r for r in map(json.loads, open(os.path.join(outdir, name + "_1.1_30.jsonl")))}
    parts = {n: load(n) for n in ("haar_alt2", "haar_profile", "haar_profile_flip")}
    print("\nunion at scale 1.1, min 30, 3 neighbours (boxes of each cascade pooled, not merged)")
    for combo in (("haar_alt2",), ("haar_alt2", "haar_profile"), ("haar_alt2", "haar_profile", "haar_profile_flip")):
        merged = []
        for img, r in parts["haar_alt2"].items():
            m = dict(r)
            m["by_neighbors"] = {"3": sum((parts[c][img]["by_neighbors"]["3"] for c in combo), [])}
            m["seconds"] = sum(parts[c][img]["seconds"] for c in combo)
            merged.append(m)
        s, fpv, fpn, ba, bn, bb, sec = score(merged, 3, sizes)
        pct = lambda g: 100.0 * s[g][0] / max(s[g][1], 1)
        print(f"{' + '.join(combo):45s} | lfw {pct('lfw'):5.1f} video {pct('video'):5.1f} 300w {s['300w'][0]}/{s['300w'][1]} "
              f"dlib {s['dlib_faces'][0]}/{s['dlib_faces'][1]} hardpose {s['hardpose'][0]}/{s['hardpose'][1]} | "
              f"FP video {fpv} nonface {fpn} | bing>=1 {100.0 * ba / max(bn, 1):.1f}% {bb / max(bn, 1):.2f}/img | "
              f"{sec / len(merged):.3f} s/img")


def image_size(path):
    data = open(path, "rb").read()
    if data[:8] == b"\x89PNG\r\n\x1a\n":
        return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")
    i = 2
    while i < len(data):
        if data[i] != 0xFF:
            i += 1
            continue
        marker = data[i + 1]
        if marker in (0xC0, 0xC1, 0xC2, 0xC3, 0xC5, 0xC6, 0xC7, 0xC9, 0xCA, 0xCB, 0xCD, 0xCE, 0xCF):
            return int.from_bytes(data[i + 7:i + 9], "big"), int.from_bytes(data[i + 5:i + 7], "big")
        i += 2 + int.from_bytes(data[i + 2:i + 4], "big")
    raise ValueError("no JPEG size in " + path)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""How often the reference detectors accept libfrig's synthetic photos, and how far dlib's 68
landmarks land from the truth (docs/synth.md, "Detector figures").

Use: bench/synth_detect.py DATASET_DIR [--dlib-ref build/tools/dlib_ref] [--opencv-ref PATH]
Runs ../shared/tools/opencv_ref.py (Haar frontal alt2, scale 1.1, 3 neighbours, min 30 px)
and dlib_ref (HOG detector upsampled once + the 68-point predictor) on every photo of the
data set, matches detections to the truth's face box (the detection's centre inside it and
its width within a factor 2), and prints detection rates for |yaw| < 30 and >= 30 degrees and
for the intended failures, and dlib's landmark error against the truth's detector-like and
exact landmarks: mean pixels and mean normalized by the outer eye-corner distance (36-45).
Needs Debian's python3-opencv (/usr/bin/python3) and dlib_ref built per its top comment.
"""
import argparse, json, math, os, subprocess, sys

here = os.path.dirname(os.path.abspath(__file__))
ap = argparse.ArgumentParser()
ap.add_argument("dataset")
ap.add_argument("--dlib-ref", default=os.path.join(here, "..", "build", "tools", "dlib_ref"))
ap.add_argument("--opencv-ref", default=os.path.join(here, "..", "..", "shared", "tools", "opencv_ref.py"))
ap.add_argument("--predictor", default="/usr/share/dlib/shape_predictor_68_face_landmarks.dat")
ap.add_argument("--json", help="also write the figures here")
a = ap.parse_args()

index = json.load(open(os.path.join(a.dataset, "index.json")))
photos = []
for s in index["subjects"]:
    for p in s["photos"]:
        t = json.load(open(os.path.join(a.dataset, p["truth"])))
        photos.append((os.path.join(a.dataset, p["photo"]), t))
paths = [p for p, _ in photos]


def run_lines(cmd):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True).stdout
    return [json.loads(l) for l in out.splitlines() if l.strip()]


cv = {}
for r in run_lines(["/usr/bin/python3", a.opencv_ref] + paths):
    cv[r["image"]] = r.get("boxes", [])
dl = {}
for r in run_lines([a.dlib_ref, a.predictor] + paths):
    dl.setdefault(r["image"], []).append(r)


def matches(truth, cx, cy, w):
    if "landmarks" not in truth:
        return False
    x0, y0, x1, y1 = truth["landmarks"]["face_box"]
    if x0 < 0:
        return False
    fw = x1 - x0 + 1
    return x0 <= cx <= x1 and y0 <= cy <= y1 and 0.5 * fw <= w <= 2.0 * fw


def group(t):
    if t["failure"] != "none":
        return t["failure"]
    return "frontal" if abs(t["pose"]["yaw_deg"]) < 30 else "turned"


stats = {}
errs = {"frontal": [], "turned": []}
for path, t in photos:
    g = group(t)
    st = stats.setdefault(g, {"photos": 0, "haar": 0, "dlib": 0, "haar_false": 0, "dlib_false": 0})
    st["photos"] += 1
    hb = [b for b in cv.get(path, []) if matches(t, b[0] + b[2] / 2, b[1] + b[3] / 2, b[2])]
    st["haar"] += bool(hb)
    st["haar_false"] += len(cv.get(path, [])) - len(hb)
    faces = dl.get(path, [])
    hit = [f for f in faces if matches(t, (f["box"][0] + f["box"][2]) / 2, (f["box"][1] + f["box"][3]) / 2,
                                      f["box"][2] - f["box"][0])]
    st["dlib"] += bool(hit)
    st["dlib_false"] += len(faces) - len(hit)
    if hit and g in errs:
        lm = hit[0]["landmarks"]
        det = t["landmarks"]["detector_like"]
        ex = t["landmarks"]["projected"]
        iod = math.dist(ex[36], ex[45])
        e_det = [math.dist(lm[k], det[k]) for k in range(68)]
        e_ex = [math.dist(lm[k], ex[k]) for k in range(68)]
        errs[g].append({"iod": iod, "det": e_det, "exact": e_ex, "photo": path})

print("%-13s %6s %12s %12s %8s %8s" % ("group", "photos", "haar alt2", "dlib HOG", "haar fp", "dlib fp"))
for g in ["frontal", "turned", "occluder", "extreme_pose", "no_face"]:
    if g not in stats:
        continue
    st = stats[g]
    n = st["photos"]
    print("%-13s %6d %6d %4.0f%% %6d %4.0f%% %8d %8d" % (g, n, st["haar"], 100.0 * st["haar"] / n, st["dlib"],
                                                   100.0 * st["dlib"] / n, st["haar_false"], st["dlib_false"]))

figures = {"detection": stats, "landmarks": {}}


def mean(v):
    return sum(v) / len(v) if v else float("nan")


print("\ndlib landmark error on its matched detections (mean over points and photos)")
print("%-9s %5s %11s %11s %11s %11s %11s" % ("group", "faces", "det px", "det /iod", "exact px", "jaw det px",
                                            "inner det px"))
for g, rows in errs.items():
    if not rows:
        continue
    det_px = mean([mean(r["det"]) for r in rows])
    det_n = mean([mean(r["det"]) / r["iod"] for r in rows])
    ex_px = mean([mean(r["exact"]) for r in rows])
    jaw = mean([mean(r["det"][:17]) for r in rows])
    inner = mean([mean(r["det"][17:]) for r in rows])
    figures["landmarks"][g] = {"faces": len(rows), "detector_like_px": det_px, "detector_like_iod": det_n,
                               "exact_px": ex_px, "jaw_px": jaw, "inner_px": inner}
    print("%-9s %5d %11.2f %11.3f %11.2f %11.2f %11.2f" % (g, len(rows), det_px, det_n, ex_px, jaw, inner))
if a.json:
    json.dump(figures, open(a.json, "w"), indent=1)

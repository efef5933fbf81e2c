#!/usr/bin/python3
# How lib/filter/face_reference.c's tables were made (run once; kept as the record).
# Input: JSON lines from ../shared/tools/dlib_ref (dlib's 68 landmarks) on the photo sets; the largest
# face of each photo is used. Output: the generalized-Procrustes mean shape (similarity-aligned,
# centred, its bounding box's larger side scaled to 1) and the Delaunay triangulation of that mean
# shape (OpenCV Subdiv2D), printed as C initializers.
# Usage: /usr/bin/python3 bench/derive_face_triangulation.py build/tools/lm_*.jsonl
import json, sys
import numpy as np
import cv2

shapes = []
for path in sys.argv[1:]:
    best = {}
    for line in open(path):
        d = json.loads(line)
        l, t, r, b = d["box"]
        area = (r - l) * (b - t)
        if d["image"] not in best or area > best[d["image"]][0]:
            best[d["image"]] = (area, np.array(d["landmarks"], float))
    shapes += [v[1] for v in best.values()]
X = np.array(shapes)  # N x 68 x 2
print("// %d faces from %d files" % (len(X), len(sys.argv) - 1), file=sys.stderr)

def to_c(s): return s[:, 0] + 1j * s[:, 1]

def align(src, dst):  # least-squares similarity src -> dst (complex regression), both centred
    a = np.vdot(src, dst) / np.vdot(src, src)
    return a * src

Z = np.array([to_c(s) - to_c(s).mean() for s in X])
mean = Z[0] / np.linalg.norm(Z[0])
for it in range(100):
    A = np.array([align(z, mean) for z in Z])
    new = A.mean(axis=0)
    new = align(new, mean)  # keep the orientation gauge of the first shape
    new /= np.linalg.norm(new)
    if np.linalg.norm(new - mean) < 1e-12:
        break
    mean = new
# Upright: the line between the outer eye corners (36, 45) horizontal.
d = mean[45] - mean[36]
mean *= abs(d) / d
pts = np.stack([mean.real, mean.imag], 1)
lo, hi = pts.min(0), pts.max(0)
pts = (pts - (lo + hi) / 2) / (hi - lo).max()

sub = cv2.Subdiv2D((-1, -1, 2, 2))
scale = 1000.0  # Subdiv2D works in float32; scale for a clean insertion
sub = cv2.Subdiv2D((-1000, -1000, 2000, 2000))
for p in pts: sub.insert((float(p[0] * scale), float(p[1] * scale)))
tris = []
for t in sub.getTriangleList():
    v = t.reshape(3, 2) / scale
    idx = [int(np.argmin(((pts - q) ** 2).sum(1))) for q in v]
    if max(np.abs(pts[idx] - v).max(1)) > 1e-4: continue  # touches the outer bounding vertices
    a, b, c = idx
    # counter-clockwise in image coordinates (y down) is clockwise on paper; store with positive
    # signed area in (x, y-down) coordinates
    cross = (pts[b, 0] - pts[a, 0]) * (pts[c, 1] - pts[a, 1]) - (pts[b, 1] - pts[a, 1]) * (pts[c, 0] - pts[a, 0])
    if cross < 0: b, c = c, b
    tris.append(tuple(sorted([(a, b, c), (b, c, a), (c, a, b)])[0]))
tris.sort()
print("/* %d triangles */" % len(tris))
print("static const double reference_shape[136] = {")
for i in range(0, 68, 4):
    print("    " + " ".join("%.6f, %.6f," % (pts[j, 0], pts[j, 1]) for j in range(i, i + 4)))
print("};")
print("static const unsigned char triangles[][3] = {")
for i in range(0, len(tris), 8):
    print("    " + " ".join("{%d, %d, %d}," % t for t in tris[i:i + 8]))
print("};")
# quality: smallest angle
def angles(t):
    P = pts[list(t)]
    out = []
    for k in range(3):
        u, v = P[(k + 1) % 3] - P[k], P[(k + 2) % 3] - P[k]
        out.append(np.degrees(np.arccos(np.dot(u, v) / np.linalg.norm(u) / np.linalg.norm(v))))
    return out
print("// smallest angle %.1f degrees" % min(min(angles(t)) for t in tris), file=sys.stderr)

/* Nearest point of a triangle: classify p against the Voronoi regions of the corners, then of
 * the edges, else project onto the plane (the method of Ericson, Real-Time Collision
 * Detection, section 5.1.5, in barycentric form). */
#include "mesh/closest_point.h"

static double dot3(const double *u, const double *v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; }

static double finish(const double p[3], const double a[3], const double b[3], const double c[3], double u,
                     double v, double w, double q[3], double bary[3]) {
    double d2 = 0;
    for (int k = 0; k < 3; k++) {
        q[k] = u * a[k] + v * b[k] + w * c[k];
        d2 += (p[k] - q[k]) * (p[k] - q[k]);
    }
    bary[0] = u, bary[1] = v, bary[2] = w;
    return d2;
}

/* Nearest point of segment (s0, s1) as the weight t of s1. */
static double segment_t(const double p[3], const double s0[3], const double s1[3]) {
    double d[3] = {s1[0] - s0[0], s1[1] - s0[1], s1[2] - s0[2]}, r[3] = {p[0] - s0[0], p[1] - s0[1], p[2] - s0[2]};
    double len2 = dot3(d, d);
    if (!(len2 > 0)) return 0;
    double t = dot3(r, d) / len2;
    return t < 0 ? 0 : t > 1 ? 1 : t;
}

double fr_closest_point_triangle(const double p[3], const double a[3], const double b[3], const double c[3],
                                 double q[3], double bary[3]) {
    double ab[3], ac[3], ap[3];
    for (int k = 0; k < 3; k++) ab[k] = b[k] - a[k], ac[k] = c[k] - a[k], ap[k] = p[k] - a[k];
    double d1 = dot3(ab, ap), d2 = dot3(ac, ap);
    if (d1 <= 0 && d2 <= 0) return finish(p, a, b, c, 1, 0, 0, q, bary); /* corner a */
    double bp[3];
    for (int k = 0; k < 3; k++) bp[k] = p[k] - b[k];
    double d3 = dot3(ab, bp), d4 = dot3(ac, bp);
    if (d3 >= 0 && d4 <= d3) return finish(p, a, b, c, 0, 1, 0, q, bary); /* corner b */
    double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0 && d1 - d3 > 0) { /* edge ab */
        double v = d1 / (d1 - d3);
        return finish(p, a, b, c, 1 - v, v, 0, q, bary);
    }
    double cp[3];
    for (int k = 0; k < 3; k++) cp[k] = p[k] - c[k];
    double d5 = dot3(ab, cp), d6 = dot3(ac, cp);
    if (d6 >= 0 && d5 <= d6) return finish(p, a, b, c, 0, 0, 1, q, bary); /* corner c */
    double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0 && d2 - d6 > 0) { /* edge ac */
        double w = d2 / (d2 - d6);
        return finish(p, a, b, c, 1 - w, 0, w, q, bary);
    }
    double va = d3 * d6 - d5 * d4;
    if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0 && (d4 - d3) + (d5 - d6) > 0) { /* edge bc */
        double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return finish(p, a, b, c, 0, 1 - w, w, q, bary);
    }
    double denom = va + vb + vc;
    if (denom > 0) { /* inside the face */
        double v = vb / denom, w = vc / denom;
        return finish(p, a, b, c, 1 - v - w, v, w, q, bary);
    }
    /* Degenerate (collinear corners): the best of the three edges. */
    double best = -1, tq[3], tb[3];
    const double *s[3][2] = {{a, b}, {b, c}, {a, c}};
    for (int e = 0; e < 3; e++) {
        double t = segment_t(p, s[e][0], s[e][1]);
        double w[3] = {0, 0, 0};
        int i0 = e == 1 ? 1 : 0, i1 = e == 0 ? 1 : 2;
        w[i0] = 1 - t, w[i1] = t;
        double d = finish(p, a, b, c, w[0], w[1], w[2], tq, tb);
        if (best < 0 || d < best) {
            best = d;
            for (int k = 0; k < 3; k++) q[k] = tq[k], bary[k] = tb[k];
        }
    }
    return best;
}

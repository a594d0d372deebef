#!/usr/bin/env python3
"""Per-frame step of an estimated trajectory next to the ground truth's.

Median and p90 of |t_i - t_(i-1)| (mm) and of the rotation angle between consecutive
poses (deg), for the estimate and for the ground truth at the same stamps (nearest
within 0.02 s). A step far larger than the ground truth's is per-frame noise; the
figures of doc/odometry.md ("Per-frame translation noise") come from:

  ./build/bin/gmc-rgbd-mapping config/bonn.ini $D/bonn_crowd_240_389 --out /tmp/s \
      --set Output.map=false --set Dataset.max_frames=70
  python3 scripts/frame_steps.py /tmp/s/trajectory_tum.txt $D/bonn_crowd_240_389/groundtruth.txt --gt-frame bonn

It also prints the per-frame step error: |estimated step - true step|, both in their own
camera frame (so it needs the camera's orientation: Bonn's marker poses are converted
with --gt-frame bonn as gmc-eval does), its median by thirds of the true rotation rate
and its correlation with it (a rolling shutter's error would grow with the rate;
doc/odometry.md, tenth round).
"""
import bisect
import math
import statistics
import sys


def read_tum(path):
    with open(path) as f:
        return [[float(v) for v in line.split()[:8]] for line in f if line.strip() and not line.startswith('#')]


def quat_matrix(q):
    x, y, z, w = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def matrix_quat(m):
    """Quaternion (x, y, z, w) of a rotation matrix (Shepperd's method)."""
    t = m[0][0] + m[1][1] + m[2][2]
    if t > 0:
        r = 2 * math.sqrt(t + 1)
        return [(m[2][1] - m[1][2]) / r, (m[0][2] - m[2][0]) / r, (m[1][0] - m[0][1]) / r, r / 4]
    i = max(range(3), key=lambda k: m[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    r = 2 * math.sqrt(1 + m[i][i] - m[j][j] - m[k][k])
    q = [0.0] * 4
    q[i], q[j], q[k], q[3] = r / 4, (m[j][i] + m[i][j]) / r, (m[k][i] + m[i][k]) / r, (m[k][j] - m[j][k]) / r
    return q


def bonn_to_camera(rows):
    """gmc::datasets::bonnBodyToCamera: ros * body * ros * marker, the published marker
    rotation made orthonormal (its polar factor, by the iteration R = (R + R^-T) / 2)."""
    r = [[1.0157, 0.1828, -0.2389], [0.0009, -0.8431, -0.6413], [-0.3009, 0.6147, -0.8085]]
    t_marker = [0.0113, -0.0098, 0.0111]
    for _ in range(50):
        (a, b, c), (d, e, f), (g, h, i) = r
        det = a * (e * i - f * h) - b * (d * i - f * g) + c * (d * h - e * g)
        inv_t = [[(e * i - f * h) / det, (f * g - d * i) / det, (d * h - e * g) / det],
                 [(c * h - b * i) / det, (a * i - c * g) / det, (b * g - a * h) / det],
                 [(b * f - c * e) / det, (c * d - a * f) / det, (a * e - b * d) / det]]
        r = [[(r[u][v] + inv_t[u][v]) / 2 for v in range(3)] for u in range(3)]
    ros = [[-1, 0, 0], [0, 0, 1], [0, 1, 0]]
    out = []
    for row in rows:
        body = quat_matrix(row[4:8])
        rot = matmul(matmul(matmul(ros, body), ros), r)
        lever = [sum(body[u][v] * sum(ros[v][w] * t_marker[w] for w in range(3)) for v in range(3)) for u in range(3)]
        pos = [sum(ros[u][v] * (row[1 + v] + lever[v]) for v in range(3)) for u in range(3)]
        out.append([row[0]] + pos + matrix_quat(rot))
    return out


def camera_step(a, b):
    """b's position in a's camera frame (m)."""
    m = quat_matrix(a[4:8])
    d = [b[k] - a[k] for k in (1, 2, 3)]
    return [sum(m[j][i] * d[j] for j in range(3)) for i in range(3)]


def angle_deg(q1, q2):
    return 2 * math.degrees(math.acos(min(1.0, abs(sum(a * b for a, b in zip(q1, q2))))))


def main():
    args = [a for a in sys.argv[1:] if a not in ('--gt-frame', 'bonn', 'camera')]
    est, gt = read_tum(args[0]), read_tum(args[1])
    if 'bonn' in sys.argv[1:]:
        gt = bonn_to_camera(gt)
    stamps = [g[0] for g in gt]

    def nearest(s):
        i = bisect.bisect_left(stamps, s)
        j = min((k for k in (i - 1, i) if 0 <= k < len(gt)), key=lambda k: abs(stamps[k] - s))
        return gt[j] if abs(stamps[j] - s) <= 0.02 else None

    rows = []
    for a, b in zip(est, est[1:]):
        ga, gb = nearest(a[0]), nearest(b[0])
        if ga and gb:
            rows.append((1000 * math.dist(a[1:4], b[1:4]), 1000 * math.dist(ga[1:4], gb[1:4]),
                         angle_deg(a[4:8], b[4:8]), angle_deg(ga[4:8], gb[4:8]),
                         1000 * math.dist(camera_step(a, b), camera_step(ga, gb))))
    if not rows:
        sys.exit('frame_steps.py: no consecutive estimated poses with ground truth within 0.02 s')

    def stat(k):
        v = sorted(r[k] for r in rows)
        return statistics.median(v), v[int(0.9 * (len(v) - 1))]

    print('translation step (mm): estimate median %.1f p90 %.1f | ground truth median %.1f p90 %.1f' %
          (*stat(0), *stat(1)))
    print('rotation step (deg):   estimate median %.2f p90 %.2f | ground truth median %.2f p90 %.2f' %
          (*stat(2), *stat(3)))
    by_rate = sorted(rows, key=lambda r: r[3])
    n = len(by_rate)
    thirds = [statistics.median(r[4] for r in by_rate[k * n // 3:(k + 1) * n // 3] or [(0, 0, 0, 0, 0)])
              for k in range(3)]
    err, rate = [r[4] for r in rows], [r[3] for r in rows]
    me, mr = statistics.mean(err), statistics.mean(rate)
    den = math.sqrt(sum((e - me) ** 2 for e in err) * sum((r - mr) ** 2 for r in rate))
    corr = sum((e - me) * (r - mr) for e, r in zip(err, rate)) / den if den > 0 else float('nan')
    print('step error (mm, camera frame): median %.1f p90 %.1f | by thirds of the rotation rate %.1f / %.1f / %.1f, '
          'correlation with it %.2f' % (*stat(4), *thirds, corr))


if __name__ == '__main__':
    main()

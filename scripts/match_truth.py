#!/usr/bin/env python3
"""Which of a run's matches against the landmark map are true, judged by a ground truth.

gmc-rgbd-mapping with Output.match_log=true writes map_matches.csv: per frame, every
match against the landmark map (with depth), with the matched point in the current
camera's frame and the observation that placed the landmark (its point in that camera's
frame and its stamp), GMC's label, whether it went into the pose refinement and whether
it is an inlier of the refinement's result. A match is *true* when both are the same
point of the world: the ground-truth poses at the two stamps take them to world points
within --tolerance (3 cm + 1 cm * z^2, z the current depth: depth noise of both readings
and the ground truth's own error). The estimated poses play no part, so a run that
drifted is judged as fairly as one that did not. A point on a person who stood still
between the two stamps is true too: it is what the pose may rest on. The 3-D tolerance
cannot see a person who moves 2 cm a frame 2 m away (5.9 cm there); --pixels PX keeps it
along the viewing ray (depth noise) and allows only PX pixels across it (--focal),
where such a walker is 5-6 px off (doc/odometry.md, forty-first round).

Prints, per tracking state (tracking, lost, ...), the frames, the matches, the true ones
(their share and the median per frame), of the matches that went into the pose the true
share, and of the refinement's inliers the true share (what the pose rests on), then
how many frames rest a tenth or more on false inliers; with --frames first one line per
frame. --split FIRST-LAST splits the matches that went into the pose over those frames
by their landmark's evidence (static / young) and verdict, and counts among them the
refinement's inliers, those placed at most --recent frames before and those nearer than
--near metres (doc/odometry.md, thirty-first round: where the false ones are young,
recent and near, walkers entered the map at a keyframe before GMC could judge them).
Where the lost frames have almost no true match, the room in view is not in the map
(doc/odometry.md, twenty-ninth round); where the pose's inliers are mostly false, the
pose follows something that moves.

  gmc-rgbd-mapping config/default.ini out/seeds/crowd_start_seed1_300 --out R \\
      --set Output.map=false --set Output.match_log=true
  scripts/match_truth.py R out/seeds/crowd_start_seed1_300/groundtruth.txt

The ground truth must be the camera's (Bonn: gmc-eval --gt-frame bonn --gt-out; TUM's
and the generated sequences' already are) and must cover the stamps; matches whose
stamps it does not cover are counted apart.
"""
import argparse
import csv
import math
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from step_changes import interpolate, read_poses, rotate  # noqa: E402


def world_point(pose, point):
    position, q = pose
    r = rotate(q, point)
    return tuple(r[k] + position[k] for k in range(3))


def judge(rows, gt, base, per_m2, pixels=None, focal=525.0):
    """Per row: True / False (the two observations are / are not one world point), or
    None when the ground truth does not cover one of the two stamps. With `pixels` the
    world distance is split along the current viewing ray (within base + per_m2 z^2, the
    depth noise) and across it (within `pixels` px at `focal`): a slow walker moves
    centimetres a frame, inside the depth tolerance but several pixels sideways."""
    stamps = [g[0] for g in gt]
    cache = {}

    def pose_at(t):
        if t not in cache:
            cache[t] = interpolate(gt, stamps, t)
        return cache[t]

    verdicts = []
    for r in rows:
        now, then = pose_at(r['stamp']), pose_at(r['origin_stamp'])
        if now is None or then is None:
            verdicts.append(None)
            continue
        z = r['point'][2]
        a, b = world_point(now, r['point']), world_point(then, r['origin'])
        distance = math.dist(a, b)
        if pixels is None:
            verdicts.append(distance <= base + per_m2 * z * z)
            continue
        rng = math.hypot(*r['point'])
        ray = rotate(now[1], tuple(c / rng for c in r['point']))
        along = sum((a[k] - b[k]) * ray[k] for k in range(3))
        across_px = math.sqrt(max(0.0, distance * distance - along * along)) / rng * focal
        verdicts.append(abs(along) <= base + per_m2 * z * z and across_px <= pixels)
    return verdicts


def read_matches(path):
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            rows.append({'frame': int(r['frame']), 'stamp': float(r['stamp']), 'state': r['state'],
                         'point': (float(r['x']), float(r['y']), float(r['z'])),
                         'origin': (float(r['origin_x']), float(r['origin_y']), float(r['origin_z'])),
                         'origin_stamp': float(r['origin_stamp']), 'label': r['label'],
                         'established': r['established'] == '1',
                         'in_pose': r['in_pose'] == '1', 'pose_inlier': r['pose_inlier'] == '1'})
    return rows


COUNTS = ('matches', 'true', 'in_pose', 'true_in_pose', 'inliers', 'true_inliers', 'uncovered')


def per_frame(rows, verdicts):
    """frame -> {'state': ..., and each of COUNTS}."""
    frames = {}
    for r, v in zip(rows, verdicts):
        f = frames.setdefault(r['frame'], dict.fromkeys(COUNTS, 0) | {'state': r['state']})
        if v is None:
            f['uncovered'] += 1
            continue
        f['matches'] += 1
        f['true'] += v
        f['in_pose'] += r['in_pose']
        f['true_in_pose'] += v and r['in_pose']
        f['inliers'] += r['pose_inlier']
        f['true_inliers'] += v and r['pose_inlier']
    return frames


def summary(frames):
    """Per state: the sums of COUNTS over its frames, 'frames', and 'median_true' per frame."""
    out = {}
    for f in frames.values():
        s = out.setdefault(f['state'], dict.fromkeys(COUNTS, 0) | {'frames': 0, 'true_per_frame': []})
        s['frames'] += 1
        s['true_per_frame'].append(f['true'])
        for key in COUNTS:
            s[key] += f[key]
    for s in out.values():
        s['median_true'] = statistics.median(s.pop('true_per_frame'))
    return out


def frames_on_false_inliers(frames, min_inliers=20, min_false=0.1):
    """(frames whose refinement inliers, min_inliers or more, are min_false or more false;
    the worst such share, 0 when none): where a pose rests partly on something that moved."""
    shares = [1 - f['true_inliers'] / f['inliers'] for f in frames.values() if f['inliers'] >= min_inliers]
    bad = [x for x in shares if x >= min_false]
    return len(bad), max(shares, default=0.0)


def frame_interval(rows):
    """The median interval between consecutive frames' stamps (s), 0 with one frame."""
    stamps = sorted({r['stamp'] for r in rows})
    steps = [b - a for a, b in zip(stamps, stamps[1:]) if b > a]
    return statistics.median(steps) if steps else 0.0


SPLIT_COUNTS = ('matches', 'inliers', 'recent', 'near')


def split_in_pose(rows, verdicts, first, last, recent_frames, near):
    """{(evidence 'static' | 'young', verdict True | False): counts of SPLIT_COUNTS} over the
    matches of frames first..last that went into the pose (judged ones only)."""
    interval = frame_interval(rows)
    out = {(e, v): dict.fromkeys(SPLIT_COUNTS, 0) for e in ('static', 'young') for v in (True, False)}
    for r, v in zip(rows, verdicts):
        if v is None or not r['in_pose'] or not first <= r['frame'] <= last:
            continue
        c = out[('static' if r['established'] else 'young', v)]
        age = (r['stamp'] - r['origin_stamp']) / interval if interval > 0 else 0.0
        c['matches'] += 1
        c['inliers'] += r['pose_inlier']
        c['recent'] += age <= recent_frames + 0.5
        c['near'] += r['point'][2] < near
    return out


def share(a, b):
    return '%5.1f %%' % (100.0 * a / b) if b else '   -   '


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('run', help='output folder of gmc-rgbd-mapping run with Output.match_log=true')
    p.add_argument('gt', help="ground truth in TUM format, the camera's poses")
    p.add_argument('--tolerance', default='0.03,0.01', metavar='BASE,PER_M2',
                   help='m: a match is true within BASE + PER_M2 * z^2 (default 0.03,0.01)')
    p.add_argument('--pixels', type=float, metavar='PX',
                   help='split the tolerance: --tolerance along the viewing ray, PX pixels across it')
    p.add_argument('--focal', type=float, default=525.0, help='--pixels: focal length in px (default 525)')
    p.add_argument('--frames', action='store_true', help='first one line per frame')
    p.add_argument('--split', metavar='FIRST-LAST',
                   help="also split those frames' matches in the pose by evidence and verdict")
    p.add_argument('--recent', type=int, default=8, help='--split: frames since placement that count as recent (8)')
    p.add_argument('--near', type=float, default=2.5, help='--split: m, depth that counts as near (2.5)')
    args = p.parse_args()
    split = None
    if args.split is not None:
        try:
            split = tuple(int(v) for v in args.split.split('-'))
            if len(split) != 2 or split[0] > split[1]:
                raise ValueError
        except ValueError:
            sys.exit('match_truth.py: --split %s: expected FIRST-LAST frame numbers' % args.split)
    matches_path = os.path.join(args.run, 'map_matches.csv')
    for path in (matches_path, args.gt):
        if not os.path.isfile(path):
            sys.exit('match_truth.py: %s: no such file (run with --set Output.match_log=true)' % path)
    try:
        base, per_m2 = (float(v) for v in args.tolerance.split(','))
    except ValueError:
        sys.exit('match_truth.py: --tolerance %s: expected BASE,PER_M2 in metres' % args.tolerance)
    try:
        rows = read_matches(matches_path)
    except (KeyError, ValueError) as e:
        sys.exit('match_truth.py: %s: not a map_matches.csv (%s)' % (matches_path, e))
    gt = read_poses(args.gt)
    if not gt:
        sys.exit('match_truth.py: %s: no poses' % args.gt)
    if args.pixels is not None and (args.pixels <= 0 or args.focal <= 0):
        sys.exit('match_truth.py: --pixels and --focal must be positive')
    verdicts = judge(rows, gt, base, per_m2, args.pixels, args.focal)
    frames = per_frame(rows, verdicts)
    if args.frames:
        print('frame state       matches  true  in pose  true in pose  inliers  true inliers')
        for frame in sorted(frames):
            f = frames[frame]
            print('%5d %-11s %7d %5d %8d %13d %8d %13d' % (frame, f['state'], f['matches'], f['true'], f['in_pose'],
                                                         f['true_in_pose'], f['inliers'], f['true_inliers']))
    uncovered = sum(f['uncovered'] for f in frames.values())
    across = ' along the ray, %g px across it' % args.pixels if args.pixels is not None else ''
    print('map matches judged against %s (true within %.3f m + %.3f m * z^2%s)%s' %
          (args.gt, base, per_m2, across, '; %d outside the ground truth, not counted' % uncovered if uncovered else ''))
    print('state       frames  matches    true (share)   true per frame, median  in pose  true (share)    '
          'inliers  true (share)')
    for state, s in sorted(summary(frames).items()):
        print('%-11s %6d %8d %7d (%s) %24g %8d %7d (%s) %8d %7d (%s)' %
              (state, s['frames'], s['matches'], s['true'], share(s['true'], s['matches']), s['median_true'],
               s['in_pose'], s['true_in_pose'], share(s['true_in_pose'], s['in_pose']), s['inliers'],
               s['true_inliers'], share(s['true_inliers'], s['inliers'])))
    count, worst = frames_on_false_inliers(frames)
    print('frames whose refinement inliers (20 or more) are 10 %% or more false: %d (worst %.0f %% false)' %
          (count, 100 * worst))
    if split:
        print('matches in the pose, frames %d-%d: landmark  verdict  matches  inliers  placed <= %d frames before  '
              'nearer than %g m' % (split[0], split[1], args.recent, args.near))
        for (evidence, verdict), c in split_in_pose(rows, verdicts, split[0], split[1], args.recent,
                                                     args.near).items():
            print('%-7s %-5s %7d %8d %26d %17d' % (evidence, 'true' if verdict else 'false', c['matches'],
                                                   c['inliers'], c['recent'], c['near']))


if __name__ == '__main__':
    main()

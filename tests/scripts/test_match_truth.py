#!/usr/bin/env python3
"""scripts/match_truth.py: map matches judged true or false by a ground truth.

  test_match_truth.py PATH/TO/match_truth.py
"""
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '../../scripts/match_truth.py')
HEADER = 'frame,stamp,state,u,v,x,y,z,origin_x,origin_y,origin_z,origin_stamp,label,established,in_pose,pose_inlier\n'


def write_run(root):
    """Camera at x = 0.5 t, turned 90 deg about y from t = 101 on. A wall point W = (1, 0, 3)
    (world) is seen from every frame; a walker's point was at (0, 0, 2) at t = 100 and is
    0.5 m further along x at t = 101. Frame 1 (t = 100.5, tracking): the wall (true, in the
    pose and an inlier), the walker (false, in the pose and an inlier: the pose followed
    it), the wall matched to a landmark placed before
    the ground truth starts (not judged). Frame 2 (t = 101.2, lost): the wall (true), the
    walker (false), both out of the pose."""
    run = os.path.join(root, 'run')
    os.makedirs(run)
    s = 0.7071067811865476
    with open(os.path.join(root, 'gt.txt'), 'w') as f:
        f.write('# timestamp tx ty tz qx qy qz qw\n')
        for i in range(31):
            t = 100 + i * 0.05
            q = '0 0 0 1' if t < 101 - 1e-9 else '0 %.16f 0 %.16f' % (s, s)
            f.write('%.6f %.6f 0 0 %s\n' % (t, 0.5 * (t - 100), q))

    def in_camera(world, t):
        x, y, z = world[0] - 0.5 * (t - 100), world[1], world[2]
        if t >= 101 - 1e-9:  # camera turned +90 deg about y: camera = R^T (world - position)
            x, z = -z, x
        return x, y, z

    rows = []

    def add(frame, t, state, world_now, world_then, then, in_pose, inlier):
        p, o = in_camera(world_now, t), in_camera(world_then, then)
        rows.append('%d,%.6f,%s,320,240,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,S,0,%d,%d\n' %
                    (frame, t, state, p[0], p[1], p[2], o[0], o[1], o[2], then, in_pose, inlier))

    wall, walker_then, walker_now = (1, 0, 3), (0, 0, 2), (0.5, 0, 2)
    add(1, 100.5, 'tracking', wall, wall, 100.0, 1, 1)
    add(1, 100.5, 'tracking', walker_now, walker_then, 100.0, 1, 1)
    add(1, 100.5, 'tracking', wall, wall, 99.0, 1, 1)
    add(2, 101.2, 'lost', wall, wall, 100.5, 0, 0)
    add(2, 101.2, 'lost', walker_now, walker_then, 100.0, 0, 0)
    with open(os.path.join(run, 'map_matches.csv'), 'w') as f:
        f.write(HEADER)
        f.writelines(rows)
    return run, os.path.join(root, 'gt.txt')


def match_lines(run):
    """The run's map_matches.csv path and its lines (header first)."""
    path = os.path.join(run, 'map_matches.csv')
    with open(path) as f:
        return path, f.read().splitlines(True)


def split_rows(stdout):
    """--split's lines: (evidence, verdict) -> [matches, inliers, recent, near]."""
    fields = (line.split() for line in stdout.splitlines())
    return {tuple(f[:2]): f[2:] for f in fields if f[:1] in (['static'], ['young'])}


def run_script(*args):
    return subprocess.run([sys.executable, SCRIPT] + list(args), capture_output=True, text=True)


def state_line(stdout, state):
    return next(line.split() for line in stdout.splitlines() if line.startswith(state + ' '))


class MatchTruth(unittest.TestCase):
    def test_a_point_that_stayed_is_true_and_one_that_moved_is_not(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root)
            r = run_script(run, gt)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn('1 outside the ground truth', r.stdout)
            # state frames matches true (share) median in_pose true_in_pose (share)
            tracking = state_line(r.stdout, 'tracking')
            self.assertEqual([tracking[1], tracking[2], tracking[3]], ['1', '2', '1'])
            self.assertEqual([tracking[8], tracking[9]], ['2', '1'])
            self.assertEqual([tracking[13], tracking[14]], ['2', '1'])
            # frame 1 has 2 judged inliers, under the 20 the count needs
            self.assertIn('10 % or more false: 0 (worst 0 % false)', r.stdout)
            lost = state_line(r.stdout, 'lost')
            self.assertEqual([lost[1], lost[2], lost[3]], ['1', '2', '1'])
            self.assertEqual([lost[8], lost[9]], ['0', '0'])

    def test_a_looser_tolerance_takes_the_walker_too(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root)
            r = run_script(run, gt, '--tolerance', '0.6,0')
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(state_line(r.stdout, 'tracking')[3], '2')

    def test_pixels_across_the_ray_catch_a_slow_walker_and_keep_depth_noise(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root)
            path, _ = match_lines(run)
            # Frame 1 (camera at x = 0.25, placed from x = 0 at t = 100): a walker 2 m away that
            # moved 2 cm sideways (inside 0.03 + 0.01 * 2^2 m, 5.25 px at f = 525), and the wall
            # point placed 2 cm too far along its ray (depth noise: true either way).
            k = 1 + 0.02 / 10 ** 0.5
            with open(path, 'a') as f:
                f.write('1,100.500000,tracking,320,240,-0.230000,0,2,0,0,2,100.000000,S,0,1,1\n')
                f.write('1,100.500000,tracking,320,240,0.750000,0,3,%.6f,0,%.6f,100.000000,S,0,1,1\n' % (k, 3 * k))
            r = run_script(run, gt)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(state_line(r.stdout, 'tracking')[3], '3')  # of 4 judged
            r = run_script(run, gt, '--pixels', '3')
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertEqual(state_line(r.stdout, 'tracking')[3], '2')
            self.assertIn('3 px across it', r.stdout)
            r = run_script(run, gt, '--pixels', '6')
            self.assertEqual(state_line(r.stdout, 'tracking')[3], '3')
            r = run_script(run, gt, '--pixels', '3', '--focal', '200')  # 2 px at f = 200
            self.assertEqual(state_line(r.stdout, 'tracking')[3], '3')
            r = run_script(run, gt, '--pixels', '0')
            self.assertNotEqual(r.returncode, 0)
            self.assertIn('--pixels', r.stderr)

    def test_frames_resting_on_false_inliers_are_counted(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root)
            path, lines = match_lines(run)
            wall, walker = lines[1], lines[2]
            # Frame 1 with 18 more wall inliers (20 in all judged) and the walker: 1 of 20 false
            # (5 %); then 2 more walker inliers: 3 of 22 (14 %).
            with open(path, 'a') as f:
                f.writelines([wall] * 18)
            r = run_script(run, gt)
            self.assertIn('10 % or more false: 0 (worst 5 % false)', r.stdout)
            with open(path, 'a') as f:
                f.writelines([walker] * 2)
            r = run_script(run, gt)
            self.assertEqual(r.returncode, 0, r.stderr)
            self.assertIn('10 % or more false: 1 (worst 14 % false)', r.stdout)

    def test_per_frame_lines(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root)
            r = run_script(run, gt, '--frames')
            self.assertEqual(r.returncode, 0, r.stderr)
            lines = r.stdout.splitlines()
            self.assertEqual(lines[1].split(), ['1', 'tracking', '2', '1', '2', '1', '2', '1'])
            self.assertEqual(lines[2].split(), ['2', 'lost', '2', '1', '0', '0', '0', '0'])

    def test_split_of_the_matches_in_the_pose(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root)
            path, lines = match_lines(run)
            # Frame 1's wall match on a landmark with static evidence; the walker's stays young.
            lines[1] = lines[1].replace(',S,0,1,1', ',S,1,1,1')
            with open(path, 'w') as f:
                f.writelines(lines)
            r = run_script(run, gt, '--split', '1-2')
            self.assertEqual(r.returncode, 0, r.stderr)
            rows = split_rows(r.stdout)
            # matches, inliers, placed <= 8 frames before (0.5 s at a 0.7 s frame interval), nearer than 2.5 m;
            # frame 2's matches are out of the pose, the third of frame 1 is not judged.
            self.assertEqual(rows[('static', 'true')], ['1', '1', '1', '0'])
            self.assertEqual(rows[('young', 'false')], ['1', '1', '1', '1'])
            self.assertEqual(rows[('young', 'true')], ['0', '0', '0', '0'])
            r = run_script(run, gt, '--split', '1-2', '--recent', '0', '--near', '1.5')
            rows = split_rows(r.stdout)
            self.assertEqual(rows[('young', 'false')], ['1', '1', '0', '0'])
            r = run_script(run, gt, '--split', '3-1')
            self.assertNotEqual(r.returncode, 0)
            self.assertIn('--split', r.stderr)

    def test_bad_input_is_named(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root)
            r = run_script(root, gt)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn('map_matches.csv', r.stderr)
            r = run_script(run, gt, '--tolerance', 'wide')
            self.assertNotEqual(r.returncode, 0)
            self.assertIn('--tolerance', r.stderr)
            with open(os.path.join(run, 'map_matches.csv'), 'w') as f:
                f.write('frame,stamp\n1,100\n')
            r = run_script(run, gt)
            self.assertNotEqual(r.returncode, 0)
            self.assertIn('not a map_matches.csv', r.stderr)


if __name__ == '__main__':
    unittest.main()

#!/usr/bin/env python3
"""scripts/step_changes.py: the rms change of the estimated and of the true step.

  test_step_changes.py PATH/TO/step_changes.py
"""
import math
import os
import random
import subprocess
import sys
import tempfile
import unittest

SCRIPT = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '../../scripts/step_changes.py')
HEADER = 'frame,stamp,state,x,y,z,qx,qy,qz,qw\n'


def write_run(root, lost_frame=None):
    """Camera moving 0.3 m/s along x. Ground truth at 100 Hz (stamps off the images'),
    estimate at 30 Hz with +-1 mm alternating along x: its step changes by 4 mm every frame."""
    run = os.path.join(root, 'run')
    os.makedirs(run)
    with open(os.path.join(root, 'gt.txt'), 'w') as f:
        f.write('# timestamp tx ty tz qx qy qz qw\n')
        for i in range(120):
            t = 99.995 + i * 0.01
            f.write('%.6f %.6f 0 0 0 0 0 1\n' % (t, 0.3 * (t - 100)))
    with open(os.path.join(run, 'tracking.csv'), 'w') as f:
        f.write(HEADER)
        for i in range(30):
            t = 100 + i / 30.0
            x = 0.3 * (t - 100) + (0.001 if i % 2 else -0.001)
            state = 'lost' if i == lost_frame else 'tracking'
            f.write('%d,%.6f,%s,%.6f,0,0,0,0,0,1\n' % (i + 1, t, state, x))
    return run, os.path.join(root, 'gt.txt')


def write_noisy_truth(root, noise_mm):
    """Camera swaying along x (5 cm at 0.5 Hz) at 30 Hz, the ground truth with white noise of
    noise_mm on x at the same stamps; the estimate is the noiseless path."""
    run = os.path.join(root, 'run')
    os.makedirs(run)
    rng = random.Random(7)
    with open(os.path.join(root, 'gt.txt'), 'w') as gt, open(os.path.join(run, 'tracking.csv'), 'w') as est:
        est.write(HEADER)
        for i in range(900):
            t = 100 + i / 30.0
            x = 0.05 * math.sin(math.pi * (t - 100))
            gt.write('%.6f %.7f 0 0 0 0 0 1\n' % (t, x + rng.gauss(0, noise_mm / 1000)))
            est.write('%d,%.6f,tracking,%.7f,0,0,0,0,0,1\n' % (i + 1, t, x))
    return run, os.path.join(root, 'gt.txt')


def translation_x(stdout):
    """(ground truth rms change, lag-1 autocorrelation, bound without noise) of translation x."""
    x = stdout.splitlines()[2].split()
    return float(x[7]), float(x[12].rstrip(',')), float(x[16])


def run_script(*args):
    return subprocess.run([sys.executable, SCRIPT] + list(args), capture_output=True, text=True)


class StepChanges(unittest.TestCase):
    def test_the_estimate_changes_by_its_scatter_and_the_interpolated_truth_not_at_all(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = run_script(*write_run(tmp))
        self.assertEqual(out.returncode, 0, out.stderr)
        lines = out.stdout.splitlines()
        self.assertIn('29 consecutive tracked steps', lines[0])
        x = lines[2].split()
        self.assertEqual(x[:2], ['translation', 'x:'])
        self.assertAlmostEqual(float(x[3]), 4.0, places=2)  # estimate, mm
        self.assertAlmostEqual(float(x[7]), 0.0, places=2)  # ground truth, mm

    def test_white_pose_noise_is_told_from_the_camera_s_own_changes(self):
        # Noiseless sway: its step changes 0.39 mm rms, smooth (lag-1 near 1), bound = rms.
        with tempfile.TemporaryDirectory() as tmp:
            out = run_script(*write_noisy_truth(tmp, 0.0))
        self.assertEqual(out.returncode, 0, out.stderr)
        true, lag1, smooth = translation_x(out.stdout)
        self.assertGreater(lag1, 0.9)
        self.assertAlmostEqual(smooth, true, places=3)
        # 1 mm white noise: changes of about sqrt(6) = 2.4 mm, lag-1 near -2/3, and the
        # bound keeps little more than the sway (up to sampling error).
        with tempfile.TemporaryDirectory() as tmp:
            out = run_script(*write_noisy_truth(tmp, 1.0))
        true, lag1, smooth = translation_x(out.stdout)
        self.assertGreater(true, 2.0)
        self.assertLess(lag1, -0.5)
        self.assertLess(smooth, 1.0)

    def test_steps_across_a_lost_frame_are_left_out(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = run_script(*write_run(tmp, lost_frame=10))
        self.assertEqual(out.returncode, 0, out.stderr)
        self.assertIn('27 consecutive tracked steps', out.stdout)

    def test_a_missing_file_is_a_one_line_error(self):
        with tempfile.TemporaryDirectory() as tmp:
            out = run_script(tmp, os.path.join(tmp, 'gt.txt'))
        self.assertNotEqual(out.returncode, 0)
        self.assertIn('tracking.csv: no such file', out.stderr)
        self.assertEqual(len(out.stderr.strip().splitlines()), 1)


if __name__ == '__main__':
    unittest.main()

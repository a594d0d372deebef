#!/usr/bin/env python3
"""scripts/error_profile.py --frames: one line per pose, tracking.csv next to the aligned error.

  test_error_profile.py PATH/TO/error_profile.py
"""
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '../../scripts/error_profile.py')
COLUMNS = ['frame', 'stamp', 'state', 'keyframe', 'matches', 'static', 'dynamic', 'inliers',
           'static_landmarks_matched', 'static_landmarks_agreeing', 'landmarks_to_refind', 'landmarks_refound',
           'position_sigma', 'pixel_error_median', 'depth_error_median', 'lost_reason']


def write_run(root, with_log=True):
    """A straight 10-frame path, 1 cm per frame; the estimate is right except frame 5 (+3 cm in y)."""
    run = os.path.join(root, 'run')
    os.makedirs(run)
    gt, est, log = [], [], []
    for i in range(10):
        t = 100 + i / 30.0
        x = 0.01 * i
        gt.append('%.6f %.4f 0 0 0 0 0 1\n' % (t, x))
        est.append('%.6f %.4f %.4f 0 0 0 0 1\n' % (t, x, 0.03 if i == 5 else 0.0))
        state = 'lost' if i == 5 else 'tracking'
        log.append(','.join([str(i + 1), '%.6f' % t, state, '1' if i == 0 else '0', '200', '150', '20', '90', '40',
                             '38', '100', '60', '0.004', '1.0', '0.01',
                             '"only 3 static inliers"' if i == 5 else '""']) + '\n')
    with open(os.path.join(root, 'gt.txt'), 'w') as f:
        f.writelines(gt)
    with open(os.path.join(run, 'trajectory_tum.txt'), 'w') as f:
        f.writelines(est)
    if with_log:
        with open(os.path.join(run, 'tracking.csv'), 'w') as f:
            f.write(','.join(COLUMNS) + '\n')
            f.writelines(log)
    return run, os.path.join(root, 'gt.txt')


def frame_rows(output):
    lines = output.splitlines()
    header = next(k for k, line in enumerate(lines) if line.startswith('frame state'))
    return [line.split() for line in lines[header + 1:header + 11]]


class Frames(unittest.TestCase):
    def run_script(self, run, gt, *extra):
        return subprocess.run([sys.executable, SCRIPT, run, gt, *extra], capture_output=True, text=True, check=True).stdout

    def test_one_line_per_pose_with_state_error_and_steps(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root)
            rows = frame_rows(self.run_script(run, gt, '--frames'))
            self.assertEqual([r[0] for r in rows], [str(i + 1) for i in range(10)])
            self.assertEqual(rows[5][1], 'lost')
            self.assertIn('only 3 static inliers', ' '.join(rows[5]))
            errors = [float(r[9]) for r in rows]
            self.assertEqual(max(range(10), key=lambda k: errors[k]), 5)  # the displaced frame
            self.assertAlmostEqual(float(rows[2][8]), 4.0, places=1)  # sigma in mm
            true_steps = [float(r[11]) for r in rows[1:]]
            for s in true_steps:
                self.assertAlmostEqual(s, 10.0, places=1)
            # The displaced frame's estimated step is longer than the camera's.
            self.assertGreater(float(rows[5][10]), 25.0)

    def test_without_tracking_log_the_columns_are_placeholders(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root, with_log=False)
            out = self.run_script(run, gt, '--frames')
            rows = frame_rows(out)
            self.assertEqual(len(rows), 10)
            self.assertEqual(rows[0][:2], ['-', '-'])
            self.assertIn('ATE', out)

    def test_without_frames_no_table(self):
        with tempfile.TemporaryDirectory() as root:
            run, gt = write_run(root)
            out = self.run_script(run, gt)
            self.assertNotIn('frame state', out)
            self.assertTrue(out.startswith('ATE'))


if __name__ == '__main__':
    unittest.main()

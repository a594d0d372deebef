#!/usr/bin/env python3
"""scripts/join_folders.py: the union of overlapping folders of one recording, and its refusals.

  test_join_folders.py PATH/TO/join_folders.py
"""
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '../../scripts/join_folders.py')
STEP = 1 / 30.0


def make_folder(root, name, frames, gt_extra=None):
    """A TUM-layout folder holding frames (indices) of one recording; images are empty files."""
    folder = os.path.join(root, name)
    for sub in ('rgb', 'depth'):
        os.makedirs(os.path.join(folder, sub))
    lists = {'rgb.txt': [], 'depth.txt': [], 'groundtruth.txt': []}
    for i in frames:
        t = 100 + i * STEP
        d = t + 0.004
        for sub, stamp in (('rgb', t), ('depth', d)):
            open(os.path.join(folder, sub, '%.6f.png' % stamp), 'w').close()
            lists[sub + '.txt'].append('%.6f %s/%.6f.png\n' % (stamp, sub, stamp))
        lists['groundtruth.txt'].append('%.6f %d 0 0 0 0 0 1\n' % (t + 0.001, gt_extra if gt_extra is not None else i))
    for name_, rows in lists.items():
        with open(os.path.join(folder, name_), 'w') as f:
            f.write('# %s\n# timestamp ...\n' % name_)
            f.writelines(rows)
    return folder


def data_lines(path):
    with open(path) as f:
        return [line.split() for line in f if line.strip() and not line.startswith('#')]


class JoinFolders(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = self.tmp.name

    def tearDown(self):
        self.tmp.cleanup()

    def run_join(self, out, *folders):
        return subprocess.run([sys.executable, SCRIPT, out] + list(folders), capture_output=True, text=True)

    def test_overlapping_folders_become_their_union_once(self):
        whole = make_folder(self.root, 'whole', list(range(0, 12)))
        a = make_folder(self.root, 'a', list(range(0, 8)))
        b = make_folder(self.root, 'b', list(range(4, 12)))
        out = os.path.join(self.root, 'joined')
        r = self.run_join(out, a, b)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn('12 frames from 2 folders', r.stdout)
        for name in ('rgb.txt', 'depth.txt', 'groundtruth.txt'):
            self.assertEqual(data_lines(os.path.join(out, name)), data_lines(os.path.join(whole, name)), name)
        # Every listed image resolves (links into the folders, nothing copied).
        for name in ('rgb.txt', 'depth.txt'):
            for _, image in data_lines(os.path.join(out, name)):
                path = os.path.join(out, image)
                self.assertTrue(os.path.islink(path), path)
                self.assertTrue(os.path.exists(path), path)
        self.assertFalse(os.path.exists(out + '.tmp'))

    def test_the_order_of_the_folders_does_not_matter(self):
        a = make_folder(self.root, 'a', list(range(0, 8)))
        b = make_folder(self.root, 'b', list(range(4, 12)))
        ab, ba = os.path.join(self.root, 'ab'), os.path.join(self.root, 'ba')
        self.assertEqual(self.run_join(ab, a, b).returncode, 0)
        self.assertEqual(self.run_join(ba, b, a).returncode, 0)
        for name in ('rgb.txt', 'depth.txt', 'groundtruth.txt'):
            self.assertEqual(data_lines(os.path.join(ab, name)), data_lines(os.path.join(ba, name)))

    def test_a_gap_between_the_folders_is_refused(self):
        a = make_folder(self.root, 'a', list(range(0, 5)))
        b = make_folder(self.root, 'b', list(range(8, 12)))
        out = os.path.join(self.root, 'joined')
        r = self.run_join(out, a, b)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn('gap', r.stderr)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1, r.stderr)
        self.assertFalse(os.path.exists(out))

    def test_a_stamp_that_disagrees_is_refused(self):
        a = make_folder(self.root, 'a', list(range(0, 8)))
        b = make_folder(self.root, 'b', list(range(4, 12)), gt_extra=7)  # another pose for the same stamps
        out = os.path.join(self.root, 'joined')
        r = self.run_join(out, a, b)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn('groundtruth.txt', r.stderr)
        self.assertFalse(os.path.exists(out))
        self.assertFalse(os.path.exists(out + '.tmp'), 'nothing half-written is left')

    def test_an_existing_output_is_not_touched(self):
        a = make_folder(self.root, 'a', list(range(0, 8)))
        out = os.path.join(self.root, 'joined')
        os.makedirs(out)
        r = self.run_join(out, a)
        self.assertNotEqual(r.returncode, 0)
        self.assertIn('exists', r.stderr)
        self.assertEqual(os.listdir(out), [])


if __name__ == '__main__':
    unittest.main()

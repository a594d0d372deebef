#!/usr/bin/env python3
"""scripts/set_eval.py: the score of a variant against a base (the doc's "better / worse (10 %)"
and geometric mean ratio), the sets' make-up, and the comparison's output.

  test_set_eval.py PATH/TO/set_eval.py
"""
import argparse
import importlib.util
import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), '../../scripts/set_eval.py')
spec = importlib.util.spec_from_file_location('set_eval', SCRIPT)
set_eval = importlib.util.module_from_spec(spec)
sys.path.insert(0, os.path.dirname(os.path.abspath(SCRIPT)))
spec.loader.exec_module(set_eval)


def runs(**ates):
    return {name.replace('_', ' '): {'ate': ate, 'still': 0.05, 'lost': 0} for name, ate in ates.items()}


class CompareSet(unittest.TestCase):
    def test_counts_moves_beyond_ten_percent_and_the_geometric_mean_of_the_ratios(self):
        base = runs(a=0.010, b=0.020, c=0.040, d=0.030)
        new = runs(a=0.005, b=0.021, c=0.080, d=0.0305)
        c = set_eval.compare_set(base, new)
        self.assertEqual(c['runs'], 4)
        self.assertEqual(c['better'], ['a'])
        self.assertEqual(c['worse'], ['c'])
        expected = math.exp((math.log(0.5) + math.log(1.05) + math.log(2.0) + math.log(0.0305 / 0.030)) / 4)
        self.assertAlmostEqual(c['geometric_mean'], expected, places=12)

    def test_only_runs_in_both_files_count(self):
        c = set_eval.compare_set(runs(a=0.01, b=0.02), runs(b=0.01, e=0.5))
        self.assertEqual(c['runs'], 1)
        self.assertEqual(c['better'], ['b'])
        self.assertAlmostEqual(c['geometric_mean'], 0.5)

    def test_an_unchanged_set_scores_one_with_nothing_moved(self):
        base = runs(a=0.01, b=0.02)
        c = set_eval.compare_set(base, base)
        self.assertEqual((c['better'], c['worse']), ([], []))
        self.assertAlmostEqual(c['geometric_mean'], 1.0)


class MedianRun(unittest.TestCase):
    def test_a_run_over_streams_is_its_median_with_every_stream_kept(self):
        figures = [{'ate': a, 'still': 0.05, 'lost': lost} for a, lost in ((0.03, 3), (0.01, 1), (1.2, 9))]
        r = set_eval.median_run(figures)
        self.assertEqual(r['ate'], 0.03)
        self.assertEqual(r['ate_per_seed'], [0.03, 0.01, 1.2])
        self.assertEqual(r['lost'], 3)  # the median stream's


class Sets(unittest.TestCase):
    def test_the_sets_have_the_sizes_the_doc_reports(self):
        with tempfile.TemporaryDirectory() as shared:
            for name in [set_eval.TEDDY] + set_eval.BONN:
                os.makedirs(os.path.join(shared, name))
            # frames 240-389 and 301-460 of one recording: joined, 221 frames
            for name, first, frames in zip(set_eval.BONN, (240, 301), (150, 160)):
                for sub in ('rgb', 'depth'):
                    os.makedirs(os.path.join(shared, name, sub))
                for listing in ('rgb.txt', 'depth.txt', 'groundtruth.txt'):
                    with open(os.path.join(shared, name, listing), 'w') as f:
                        f.writelines('%d rgb/%d.png\n' % (i, i) for i in range(first, first + frames))
            args = argparse.Namespace(data='out/seeds', shared=shared, work_dir=shared)
            sizes = {s: len(set_eval.runs_of(s, args)) for s in set_eval.SETS}
            joined = [r for r in set_eval.runs_of('bonn', args) if r[0].startswith('240_460')]
        self.assertEqual(sizes, {'choice': 23, 'held': 18, 'other': 22, 'bonn': 32, 'teddy': 5})
        self.assertEqual([(r[0], r[3], r[4]) for r in joined[:2]], [('240_460 whole', 0, 0), ('240_460 window +0', 0, 150)])
        self.assertEqual(joined[-1][0], '240_460 window +70')

    def test_the_spread_gives_each_run_over_its_streams_and_every_stream_run(self):
        runs = {'teddy +0': {'ate': 0.004, 'ate_per_seed': [0.005, 0.003, 0.004]},
                'teddy +3': {'ate': 0.002}}
        self.assertEqual(set_eval.spread_lines(runs),
                         ['teddy +0                     0.0040 [0.0030-0.0050] over 3 streams',
                          'teddy +3                     0.0020 [0.0020-0.0020] over 1 stream',
                          'all 4 stream-runs: median 0.0035, max 0.0050'])

    def test_absent_real_folders_are_skipped_not_run(self):
        with tempfile.TemporaryDirectory() as shared:
            args = argparse.Namespace(data='out/seeds', shared=shared)
            names = [r[0] for r in set_eval.runs_of('choice', args)]
            self.assertEqual(len(names), 18)
            self.assertFalse(any(n.startswith('teddy') for n in names))
            self.assertEqual(set_eval.runs_of('bonn', args), [])


    def test_the_runs_read_the_frozen_configs_when_given(self):
        with tempfile.TemporaryDirectory() as shared:
            os.makedirs(os.path.join(shared, set_eval.TEDDY))
            args = argparse.Namespace(data='out/seeds', shared=shared, config_dir='/frozen/config')
            configs = {r[1] for r in set_eval.runs_of('choice', args)}
            self.assertEqual(configs, {'/frozen/config/default.ini', '/frozen/config/tum_fr3.ini'})
            del args.config_dir
            self.assertIn('config/default.ini', {r[1] for r in set_eval.runs_of('choice', args)})


class CompareOverStreams(unittest.TestCase):
    def test_each_stream_is_scored_against_the_same_stream_and_failures_are_counted(self):
        base = {'a': {'ate': 0.02, 'ate_per_seed': [0.01, 0.02, 0.04], 'still': 0.05, 'lost': 0},
                'b': {'ate': 0.02, 'ate_per_seed': [0.02, 0.02, 0.02], 'still': 0.05, 'lost': 0}}
        new = {'a': {'ate': 0.02, 'ate_per_seed': [0.02, 0.02, 0.01], 'still': 0.05, 'lost': 0},
               'b': {'ate': 0.02, 'ate_per_seed': [0.02, 0.9, 0.02], 'still': 0.05, 'lost': 0}}
        c = set_eval.compare_set(base, new)
        self.assertAlmostEqual(c['geometric_mean'], 1.0)  # the medians did not move
        self.assertAlmostEqual(c['per_stream'][0], math.sqrt(2.0))
        self.assertAlmostEqual(c['per_stream'][1], math.sqrt(45.0))
        self.assertAlmostEqual(c['per_stream'][2], math.sqrt(0.25))
        self.assertEqual(c['failed_stream_runs'], 1)
        # Without stream-runs that fail in either file: b's stream 1 (0.9 m) is left out.
        self.assertAlmostEqual(c['per_stream_settled'][0], math.sqrt(2.0))
        self.assertAlmostEqual(c['per_stream_settled'][1], 1.0)
        self.assertAlmostEqual(c['per_stream_settled'][2], math.sqrt(0.25))

    def test_runs_of_a_single_stream_have_no_per_stream_score(self):
        c = set_eval.compare_set(runs(a=0.01), runs(a=0.02))
        self.assertEqual(c['per_stream'], [])


class CompareCommand(unittest.TestCase):
    def test_prints_each_set_and_the_runs_that_moved(self):
        with tempfile.TemporaryDirectory() as tmp:
            for name, ates in (('base', runs(a=0.01, b=0.02)), ('new', runs(a=0.02, b=0.02))):
                with open(os.path.join(tmp, name + '.json'), 'w') as f:
                    json.dump({'set': [], 'random_seeds': 1, 'runs': {'choice': ates}}, f)
            out = subprocess.run([sys.executable, SCRIPT, 'compare', os.path.join(tmp, 'base.json'),
                                  os.path.join(tmp, 'new.json')], check=True, capture_output=True, text=True).stdout
        self.assertIn('choice: 2 runs, 0 better / 1 worse (10 %), geometric mean ratio 1.414', out)
        self.assertIn('a', out.splitlines()[1])
        self.assertIn('0.0100 -> 0.0200', out)


class ConfigDigest(unittest.TestCase):
    def test_a_changed_default_changes_the_digest_and_compare_says_so(self):
        with tempfile.TemporaryDirectory() as tmp:
            config = os.path.join(tmp, 'config')
            os.makedirs(os.path.join(config, 'sim'))
            with open(os.path.join(config, 'default.ini'), 'w') as f:
                f.write('[Odometry]\nunheld_start_frames = 0\n')
            with open(os.path.join(config, 'sim', 'crowd.ini'), 'w') as f:
                f.write('[Sim]\n')
            before = set_eval.config_digest(config)
            self.assertEqual(before, set_eval.config_digest(config))
            with open(os.path.join(config, 'default.ini'), 'w') as f:
                f.write('[Odometry]\nunheld_start_frames = 12\n')
            after = set_eval.config_digest(config)
            self.assertNotEqual(before, after)

            def compared(digest_base, digest_new):
                for name, digest in (('base', digest_base), ('new', digest_new)):
                    with open(os.path.join(tmp, name + '.json'), 'w') as f:
                        json.dump({'set': [], 'random_seeds': 1, 'config_digest': digest,
                                   'runs': {'choice': runs(a=0.01)}}, f)
                return subprocess.run([sys.executable, SCRIPT, 'compare', os.path.join(tmp, 'base.json'),
                                       os.path.join(tmp, 'new.json')], check=True, capture_output=True,
                                      text=True).stdout
            self.assertIn('note: the two files read different config/ folders', compared(before, after))
            self.assertNotIn('note:', compared(before, before))
            self.assertNotIn('note:', compared(None, after))  # files written before the digest


class StreamMoves(unittest.TestCase):
    def test_every_stream_run_that_moved_beyond_the_share_is_listed(self):
        base = {'a': {'ate': 0.02, 'ate_per_seed': [0.010, 0.020, 0.040]}, 'b': {'ate': 0.02, 'ate_per_seed': [0.02] * 3}}
        new = {'a': {'ate': 0.02, 'ate_per_seed': [0.0104, 0.020, 0.030]}, 'b': {'ate': 0.02, 'ate_per_seed': [0.02] * 3},
               'c': {'ate': 0.9, 'ate_per_seed': [0.9] * 3}}
        self.assertEqual(set_eval.stream_moves(base, new, 0.05), [('a', 2, 0.040, 0.030)])
        self.assertEqual(set_eval.stream_moves(base, new, 0.03), [('a', 0, 0.010, 0.0104), ('a', 2, 0.040, 0.030)])


class ScenarioTable(unittest.TestCase):
    def test_generated_runs_are_grouped_by_scenario_over_sets_and_real_runs_left_out(self):
        runs = {'choice': {'crowd 1': {'ate': 0.01, 'ate_per_seed': [0.01, 0.02], 'still': 0.2},
                           'teddy +3': {'ate': 0.003, 'still': 0.1},
                           'crowd_hover 2': {'ate': 0.03, 'still': 0.08}},
                'held': {'crowd 11': {'ate': 0.06, 'ate_per_seed': [0.06, 0.05], 'still': 0.2}},
                'bonn': {'240_389 window +10': {'ate': 0.03, 'still': 0.05},
                         '301_460 start 3': {'ate': 0.02, 'still': 0.05}}}
        t = set_eval.scenario_table(runs)
        self.assertEqual(sorted(t), ['crowd', 'crowd_hover'])
        self.assertEqual(t['crowd'], [(1, 0.01, [0.01, 0.02], 0.2), (11, 0.06, [0.06, 0.05], 0.2)])
        self.assertEqual(t['crowd_hover'], [(2, 0.03, [0.03], 0.08)])


def bonn_runs():
    """Two streams of one folder: stream 1's window +10 ends above its standing still."""
    def r(ates, still):
        return {'ate': sorted(ates)[len(ates) // 2], 'ate_per_seed': ates, 'still': still, 'lost': 0}
    return {'301_460 whole': r([0.020, 0.025], 0.052), '301_460 window +0': r([0.010, 0.012], 0.060),
            '301_460 window +10': r([0.030, 0.055], 0.050), '301_460 window +20': r([0.020, 0.016], 0.040),
            '301_460 start 3': r([0.021, 0.030], 0.051), '301_460 start 6': r([0.024, 0.019], 0.049)}


class WindowTable(unittest.TestCase):
    def test_each_stream_gets_its_whole_folder_windows_against_standing_still_and_starts(self):
        t = set_eval.window_table(bonn_runs())['301_460']
        self.assertEqual(t[0]['whole'], (0.020, 0.052))
        self.assertEqual((t[0]['window_median'], t[0]['window_max']), (0.020, 0.030))
        self.assertEqual((t[0]['below_still'], t[0]['windows'], t[0]['above_still']), (3, 3, []))
        self.assertEqual(t[0]['starts'], (0.021, 0.024))
        self.assertEqual((t[1]['window_median'], t[1]['window_max']), (0.016, 0.055))
        self.assertEqual((t[1]['below_still'], t[1]['above_still']), (2, [(10, 0.055, 0.050)]))
        self.assertEqual(t[1]['starts'], (0.019, 0.030))

    def test_the_command_prints_a_line_per_stream_and_needs_the_bonn_set(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, 'set.json')
            with open(path, 'w') as f:
                json.dump({'runs': {'bonn': bonn_runs()}}, f)
            out = subprocess.run([sys.executable, SCRIPT, 'windows', path], check=True, capture_output=True,
                                 text=True).stdout.splitlines()
            self.assertEqual(len(out), 2)
            self.assertIn('301_460 stream 1: whole 0.0250 (standing still 0.0520)', out[1])
            self.assertIn('below standing still 2 of 3; +10 0.0550 against 0.0500', out[1])
            with open(path, 'w') as f:
                json.dump({'runs': {'choice': {}}}, f)
            bad = subprocess.run([sys.executable, SCRIPT, 'windows', path], capture_output=True, text=True)
            self.assertNotEqual(bad.returncode, 0)
            self.assertIn('no bonn set', bad.stderr)


if __name__ == '__main__':
    unittest.main()

#!/usr/bin/env python3
"""The figures a refactor must keep identical (docs/performance.md, "Checking that a change keeps
the figures"): the work counters of `hrpp predict --json` (walks, TP/FP/FN/TN, wrong results,
updates per ray kind; not timings, not cost-model cycles) on every shared and own scene, in all
three modes, for the RTL `primary` configuration's table and for an unbounded faithful table at
go-up 1; and everything `tb_hrpp` prints (but its timing line) for every tb.* command of the
test suite.

  figures.py capture --hrpp BIN --tb BIN --build BUILDDIR --out DIR [--shared DIR]
      [--only predict|tb] [--workers N | --scheduler ADDRESS | --no-dask] [--resume]
  figures.py compare DIR_A DIR_B      exit 1 when any figure differs or is missing
  figures.py compare DIR_A DIR_B --moved
                                      also say by how much: per differing predict report its
                                      work counters (baseline and HRPP interior-node tests, leaf
                                      visits, triangle tests) and skipped fraction, A -> B; per
                                      differing tb_hrpp output its changed lines

Capture with the binaries before a change (copy them first) and after it, then compare.

Each run of the capture is a task of the study driver (pyhrpp/study.py): --workers N runs at a time
on a local Dask cluster (--jobs is the same option), --scheduler ADDRESS on a running one,
--no-dask one after another; the journal OUT/journal.jsonl lets --resume continue an interrupted
capture. A predict run that fails stops it; a tb_hrpp run's exit code is one of its figures."""
import argparse
import glob
import json
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

sys.path.insert(0, ROOT)  # the pyhrpp package
from pyhrpp import rtl_config  # noqa: E402  (rtl/config/hrpp_configs.json)
from pyhrpp import study  # noqa: E402
from pyhrpp.files import write_atomic  # noqa: E402

# 'rtl': the RTL `primary` table as explicit options (what --preset rtl-primary selects), so that
# binaries from before the presets run it too; 'unb': the study's unbounded table at go-up 1.
CONFIGS = {
    'rtl': ' '.join(rtl_config.predict_args(rtl_config.config('primary'))),
    'unb': '--hash faithful --precision 6 --table unbounded --go-up 1',
}
MODES = ['anyhit', 'closest-exact', 'closest-spec']
# 'bvh': the report's description of the BVH (builder, statistics, build time), which captures of
# binaries from before it lack; a BVH that changed shows in the work counters.
DROP = {'time', 'preset', 'baseline_ns', 'hrpp_ns', 'seconds', 'cost', 'cost_model', 'threads', 'scene',
        'tool', 'table_unbounded', 'bvh'}
# Keys renamed since the first captures (issue 20), stored under their old names so that captures
# of binaries from before and after compare.
RENAMED = {'precision_bits': 'precision'}

def untimed_args(hrpp, cache={}):
    """`--timing cost-model` for binaries that simulate time by default (issue 20): the work
    counters are the same either way, the simulation is only slower."""
    if hrpp not in cache:
        h = subprocess.run([hrpp, 'predict', '--help'], capture_output=True, text=True).stdout
        cache[hrpp] = ['--timing', 'cost-model'] if '--timing' in h else []
    return cache[hrpp]


def strip(d):
    if isinstance(d, dict):
        out = {RENAMED.get(k, k): strip(v) for k, v in d.items() if k not in DROP}
        if 'pipeline_latency' in out and out['pipeline_latency'] is None:
            out['pipeline_latency'] = -1  # none given: null since issue 20, -1 before
        return out
    if isinstance(d, list):
        return [strip(v) for v in d]
    return d

def predict_task(hrpp, scene, cname, mode):
    """`hrpp predict` on SCENE in configuration CNAME and MODE; its report stays in the result
    (write_predict stores its figures)."""
    own = os.path.dirname(os.path.abspath(scene)) == os.path.join(ROOT, 'scenes')
    name = f"{'own-' if own else ''}{os.path.basename(scene)[:-4]}.{cname}.{mode}"
    cmd = [hrpp, 'predict', scene, *CONFIGS[cname].split(), '--mode', mode, '--res', '200x150',
           '--json', '{json}'] + untimed_args(hrpp)
    return study.Task(key=('predict', name), cmd=cmd, files={'json': None})

def write_predict(out, task, result):
    write_atomic(os.path.join(out, 'predict', task.key[1] + '.json'),
                 json.dumps(strip(json.loads(result.files['json'])), indent=1, sort_keys=True))

TB_DROP = re.compile(r'^(timing:|tb_hrpp: wrote|trace)')

def tb_task(tb, test):
    """TEST (name, ctest command) with the tb_hrpp binary TB; its exit code and output are its
    figures (write_tb)."""
    name, cmd = test
    cmd = [tb if os.path.basename(c) in ('tb_hrpp',) else c for c in cmd]
    # Any exit code is a finished run: it is one of the run's figures.
    return study.Task(key=('tb', name), cmd=cmd, report=None, ok=None)

def write_tb(out, task, result):
    lines = [l for l in (result.stdout + result.stderr).splitlines() if not TB_DROP.match(l)]
    lines = [re.sub(r'\d+\.\d+ s \(CPU [^)]*\)', 'T', l) for l in lines]
    write_atomic(os.path.join(out, 'tb', task.key[1] + '.txt'),
                 f"rc {result.rc}\n" + '\n'.join(lines) + '\n')

def tb_tests(build):
    r = subprocess.run(['ctest', '--show-only=json-v1'], cwd=build, capture_output=True, text=True)
    tests = json.loads(r.stdout)['tests']
    res = []
    for t in tests:
        cmd = t.get('command') or []
        if t['name'].startswith('tb.') and cmd and os.path.basename(cmd[0]) == 'tb_hrpp':
            res.append((t['name'], cmd))
    return res

WORK = ('interior_tests', 'leaf_visits', 'tri_tests')


def moved(kind, ta, tb):
    """How one figure moved from A to B: a predict report's work counters and skipped fraction
    (relative changes), or a testbench output's changed lines."""
    if kind == 'tb':
        la, lb = ta.splitlines(), tb.splitlines()
        return '\n'.join(f'    - {x}\n    + {y}' for x, y in zip(la, lb) if x != y) + (
            f'\n    ({len(la)} / {len(lb)} lines)' if len(la) != len(lb) else '')
    da, db = json.loads(ta), json.loads(tb)
    out = []
    for side in ('baseline', 'hrpp'):
        parts = []
        for k in WORK:
            x, y = da.get(side, {}).get(k), db.get(side, {}).get(k)
            if x != y and x is not None and y is not None:
                parts.append(f'{k} {x} -> {y} ({100 * (y - x) / max(1, x):+.3f}%)')
        if parts:
            out.append(f'    {side}: ' + ', '.join(parts))
    x, y = da.get('skipped_interior_fraction'), db.get('skipped_interior_fraction')
    if x != y and x is not None and y is not None:
        out.append(f'    skipped interior fraction {100 * x:.3f}% -> {100 * y:.3f}%')
    for k in ('wrong_results', 'true_positive', 'false_positive', 'exact_mismatches'):
        if da.get(k) != db.get(k):
            out.append(f'    {k} {da.get(k)} -> {db.get(k)}')
    return '\n'.join(out) or '    (only other fields)'


def capture(a):
    """The capture: every predict and tb_hrpp run a study task, their figures in A.out."""
    identity = {'hrpp': None if a.only == 'tb' else study.tool_version(a.hrpp),
                'tb_hrpp': None if a.only == 'predict' else study.tool_version(a.tb)}
    os.makedirs(os.path.join(a.out, 'predict'), exist_ok=True)
    os.makedirs(os.path.join(a.out, 'tb'), exist_ok=True)
    scenes = (sorted(glob.glob(os.path.join(a.shared, 'scenes', '*.glb'))) +
              sorted(glob.glob(os.path.join(ROOT, 'scenes', '*.glb'))))
    if not glob.glob(os.path.join(a.shared, 'scenes', '*.glb')):
        print(f'figures: no shared scenes in {a.shared}/scenes: own scenes only')
    tasks = []
    if a.only != 'tb':
        tasks += [predict_task(a.hrpp, s, cn, md) for s in scenes for cn in CONFIGS for md in MODES]
    if a.only != 'predict':
        tasks += [tb_task(a.tb, t) for t in tb_tests(a.build)]
    with study.Study('figures', os.path.join(a.out, 'journal.jsonl'), identity, a) as st:
        results = st.run(tasks, summary=lambda t, r: '' if t.key[0] == 'predict' else f'rc {r.rc}')
        for t, r in zip(tasks, results):
            (write_predict if t.key[0] == 'predict' else write_tb)(a.out, t, r)
        st.complete()
    print('captured', len(tasks))
    return 0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    sub = ap.add_subparsers(dest='cmd', required=True)
    c = sub.add_parser('capture', help='run the tools and store their figures in OUT')
    c.add_argument('--hrpp', help='the hrpp binary (predict figures)')
    c.add_argument('--tb', help='the tb_hrpp binary (testbench figures)')
    c.add_argument('--build', help='a configured build folder: its tb.* ctest commands')
    c.add_argument('--out', required=True, help='folder for the figures')
    c.add_argument('--shared', default=os.path.join(ROOT, '..', 'shared'),
                   help='the shared folder (its scenes/*.glb)')
    c.add_argument('--only', choices=['predict', 'tb'], help='capture only these figures')
    study.add_arguments(c)
    m = sub.add_parser('compare', help='compare two captures (exit 1 when any figure differs)')
    m.add_argument('a')
    m.add_argument('b')
    m.add_argument('--moved', action='store_true',
                   help='print how each differing figure moved (work counters first)')
    a = ap.parse_args()
    if a.cmd == 'capture':
        need = [] if a.only == 'tb' else ['hrpp']
        need += [] if a.only == 'predict' else ['tb', 'build']
        for n in need:
            if not getattr(a, n):
                ap.error(f'capture needs --{n}' + ('' if a.only else ' (or --only)'))
    if a.cmd == 'capture':
        sys.exit(study.main_errors('figures', lambda: capture(a)))
    else:
        bad = 0; n = 0
        for sub_ in ('predict', 'tb'):
            fa = sorted(os.listdir(os.path.join(a.a, sub_)))
            fb = set(os.listdir(os.path.join(a.b, sub_)))
            for f in fa:
                n += 1
                if f not in fb:
                    print('missing in B:', sub_, f)
                    bad += 1
                    continue
                with open(os.path.join(a.a, sub_, f)) as x, open(os.path.join(a.b, sub_, f)) as y:
                    tx, ty = x.read(), y.read()
                    if tx != ty:
                        print('DIFFERS:', sub_, f)
                        bad += 1
                        if a.moved:
                            print(moved(sub_, tx, ty))
        print(f'{n} compared, {bad} differ')
        sys.exit(1 if bad else 0)

if __name__ == '__main__':  # not in the Dask workers, which import this module
    main()

#!/usr/bin/env python3
"""Checks cmkit against the original's answers on the bundled lt4 map (data/reference/lt4).

usage: check_lt4.py CMKIT_BINARY REPO_ROOT WORK_DIR [--report]

1. `cmkit compile data/maps/lt4/lt4.map -o WORK_DIR/lt4.cm` must write a file whose SHA-256 is
   the one of the .cm the original wrote for lt4 (data/reference/lt4/lt4.cm.sha256).
2. `cmkit query` answers the sampled queries (data/reference/lt4/lt4.queries.txt); each answer is
   judged against the original's (lt4.results.txt) by these rules, per operation:
   - translation, rotation, contents: |fraction - ref| <= 1e-4 and end position within 1e-2 per
     coordinate (and for contents the same result value); when the reference hit something
     (fraction < 1) the contact normal within 1e-3, else the line is a "tie" (two surfaces
     equally near: which one is reported depends on the traversal order);
   - pointcontents: the same contents value. cmkit answers the OR of every brush holding the point,
     the original the first brush it finds in one leaf (docs/fidelity.md, "Point contents is what
     the point is in"), so an answer that holds every bit of the original's and more is counted as
     "documented", not as a disagreement;
   - contacts: the same count;
   - an error line agrees only with an error line; translations of a trace model longer than 4096
     units are left out (the original refuses them).
Prints one row per operation. Exit status 1 on a .cm mismatch or on any line that is neither
agree, tie nor documented (with --report: 0 unless a command fails; ./dev.sh fidelity).
"""
import hashlib
import math
import os
import subprocess
import sys

FRAC_EPS = 1e-4
POS_EPS = 1e-2
NORMAL_EPS = 1e-3


def fields(line):
    return dict(tok.split('=', 1) for tok in line.split() if '=' in tok)


def numbers(text):
    try:
        return [float(x) for x in text.split(',')]
    except (AttributeError, ValueError):
        return None


def within(a, b, eps):
    return a is not None and b is not None and len(a) == len(b) and all(abs(x - y) <= eps for x, y in zip(a, b))


def too_long_for_original(query):
    f = fields(query)
    if query.split()[0] != 'translation' or f.get('trm', 'point') == 'point':
        return False
    start, end = numbers(f.get('start')), numbers(f.get('end'))
    return bool(start and end) and math.dist(start, end) > 4096.0


def verdict(op, ref, got):
    if 'error' in ref or 'error' in got:
        return 'agree' if 'error' in ref and 'error' in got else 'error mismatch'
    if op == 'pointcontents':
        if ref.get('contents') == got.get('contents'):
            return 'agree'
        r, g = int(ref.get('contents', '-1')), int(got.get('contents', '-1'))
        return 'documented' if r >= 0 and g >= 0 and (r & g) == r else 'contents'
    if op == 'contacts':
        return 'agree' if ref.get('count') == got.get('count') else 'count'
    fr = numbers(ref.get('fraction'))
    if not within(fr, numbers(got.get('fraction')), FRAC_EPS):
        return 'fraction'
    if not within(numbers(ref.get('endpos')), numbers(got.get('endpos')), POS_EPS):
        return 'endpos'
    if op == 'contents' and ref.get('result') != got.get('result'):
        return 'result'
    if fr[0] < 1.0 and not within(numbers(ref.get('normal')), numbers(got.get('normal')), NORMAL_EPS):
        return 'tie'
    return 'agree'


def run(cmd):
    done = subprocess.run(cmd, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f'FAILED ({done.returncode}): {" ".join(cmd)}\n{done.stdout}{done.stderr}')


def main():
    args = [a for a in sys.argv[1:] if a != '--report']
    report = '--report' in sys.argv
    if len(args) != 3:
        sys.exit(__doc__)
    cmkit, root, work = args
    os.makedirs(work, exist_ok=True)
    ref_dir = os.path.join(root, 'data', 'reference', 'lt4')
    map_path = os.path.join(root, 'data', 'maps', 'lt4', 'lt4.map')
    failed = False

    cm_path = os.path.join(work, 'lt4.cm')
    run([cmkit, 'compile', map_path, '--no-proc', '-q', '-o', cm_path])
    with open(cm_path, 'rb') as f:
        got_hash = hashlib.sha256(f.read()).hexdigest()
    with open(os.path.join(ref_dir, 'lt4.cm.sha256')) as f:
        ref_hash = f.read().split()[0]
    same = got_hash == ref_hash
    failed |= not same
    print(f".cm            {'byte-identical to the original' if same else 'DIFFERS from the original'}"
          f" (sha256 {got_hash})")

    queries_path = os.path.join(ref_dir, 'lt4.queries.txt')
    results_path = os.path.join(work, 'lt4.results.txt')
    run([cmkit, 'query', map_path, queries_path, '--no-proc', '-o', results_path])
    with open(queries_path) as f:
        queries = [l for l in f.read().splitlines() if l.strip() and not l.lstrip().startswith('#')]
    with open(os.path.join(ref_dir, 'lt4.results.txt')) as f:
        ref = f.read().splitlines()
    with open(results_path) as f:
        got = f.read().splitlines()
    if not (len(queries) == len(ref) == len(got)):
        sys.exit(f'FAILED: {len(queries)} queries, {len(ref)} reference lines, {len(got)} answers')

    rows = {}
    bad = []
    for n, (q, r, g) in enumerate(zip(queries, ref, got), 1):
        op = q.split()[0]
        row = rows.setdefault(op, {'lines': 0, 'agree': 0, 'tie': 0, 'documented': 0, 'left out': 0, 'differ': 0})
        if too_long_for_original(q):
            row['left out'] += 1
            continue
        v = verdict(op, fields(r), fields(g))
        row['lines'] += 1
        if v in row:
            row[v] += 1
        else:
            row['differ'] += 1
            bad.append((n, v, q, r, g))
    for op, row in sorted(rows.items()):
        pct = 100.0 * row['agree'] / row['lines'] if row['lines'] else 100.0
        print(f"{op:14s} {row['lines']:4d} lines  agree {row['agree']:4d} ({pct:6.2f} %)  tie {row['tie']:3d}"
              f"  documented {row['documented']:3d}  differ {row['differ']:3d}  left out {row['left out']:3d}")
    total = {k: sum(row[k] for row in rows.values()) for k in ('lines', 'agree', 'tie', 'documented', 'differ')}
    print(f"{'all':14s} {total['lines']:4d} lines  agree {total['agree']:4d} "
          f"({100.0 * total['agree'] / max(total['lines'], 1):6.2f} %)  tie {total['tie']:3d}"
          f"  documented {total['documented']:3d}  differ {total['differ']:3d}")
    for n, v, q, r, g in bad[:10]:
        print(f'\nline {n} ({v})\n  query:    {q}\n  original: {r}\n  cmkit:    {g}')
    failed |= bool(bad)
    if failed and not report:
        print('FAILED: see above (docs/fidelity.md)')
        return 1
    print('OK: lt4 .cm and sampled queries agree with the original' if not failed else 'differences: see above')
    return 0


if __name__ == '__main__':
    sys.exit(main())

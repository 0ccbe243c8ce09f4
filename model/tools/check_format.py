#!/usr/bin/env python3
"""The C++ formatting check of `make lint` and `make test` (ctest lint.format).

Every tracked C++ source and header (model/, tb/, fuzz/) must be exactly what clang-format (the
version pinned in requirements.txt, with the repository's .clang-format) makes of it, and no line
may exceed 100 columns (clang-format leaves some long lines alone, e.g. long string literals).

  check_format.py [--clang-format BIN] [--fix]

--fix rewrites the files in place instead of checking them. Exit 0: clean; 1: files to format,
each named with its first differing line; 2: usage error or clang-format missing."""
import argparse
import difflib
import os
import shutil
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DIRS = ('model', 'tb', 'fuzz')
EXTS = ('.cc', '.h', '.cpp', '.hpp')
LIMIT = 100


def sources():
    try:
        out = subprocess.run(['git', 'ls-files', '--', *DIRS], cwd=ROOT, capture_output=True,
                             text=True, check=True).stdout.split()
    except (OSError, subprocess.CalledProcessError):
        out = [os.path.relpath(os.path.join(d, f), ROOT)
               for top in DIRS for d, _, fs in os.walk(os.path.join(ROOT, top)) for f in fs]
    return sorted(f for f in out if f.endswith(EXTS) and os.path.isfile(os.path.join(ROOT, f)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    default = os.path.join(os.path.dirname(sys.executable), 'clang-format')
    ap.add_argument('--clang-format', default=default if os.path.exists(default) else
                    shutil.which('clang-format') or 'clang-format')
    ap.add_argument('--fix', action='store_true', help='format the files in place')
    a = ap.parse_args()
    try:
        version = subprocess.run([a.clang_format, '--version'], capture_output=True, text=True,
                                 check=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError) as e:
        print(f'check_format: cannot run {a.clang_format}: {e} (make setup installs it)',
              file=sys.stderr)
        return 2
    files = sources()
    if a.fix:
        subprocess.run([a.clang_format, '-i', *files], cwd=ROOT, check=True)
    bad = 0
    for f in files:
        path = os.path.join(ROOT, f)
        text = open(path, encoding='utf-8').read()
        formatted = subprocess.run([a.clang_format, f'--assume-filename={f}'], input=text,
                                   cwd=ROOT, capture_output=True, text=True, check=True).stdout
        if formatted != text:
            bad += 1
            first = next((i for i, (x, y) in enumerate(zip(text.splitlines(),
                                                           formatted.splitlines())) if x != y),
                         min(len(text.splitlines()), len(formatted.splitlines())))
            diff = difflib.unified_diff(text.splitlines(), formatted.splitlines(), lineterm='',
                                        n=0)
            shown = [l for l in list(diff)[2:8]]
            print(f'{f}:{first + 1}: not clang-formatted', *('    ' + l for l in shown),
                  sep='\n')
        for n, line in enumerate(text.splitlines(), 1):
            if len(line) > LIMIT:
                bad += 1
                print(f'{f}:{n}: {len(line)} columns (limit {LIMIT})')
    print(f'check_format: {len(files)} files, {version}: '
          + ('clean' if not bad else f'{bad} problems (fix: {sys.argv[0]} --fix)'))
    return 1 if bad else 0


if __name__ == '__main__':
    sys.exit(main())

#!/usr/bin/env python3
"""Worst-case stack depth of lib/ from GCC's -fcallgraph-info=su files.

usage: stack_report.py [--max BYTES] [--hook FUNCTION]...
                       [--edge CALLER=CALLEE[,CALLEE...]]... DIR_OR_CI_FILES...

For every function defined in the .ci files, the worst depth is its own
frame plus the deepest callee. Calls to functions without a frame record
(libc's memset/memcpy, compiler builtins) count as 0 bytes. Recursion,
dynamic frames (VLA/alloca) and calls through pointers that the graph
cannot follow make the bound unknowable: each is reported and fails.
The one exception are the documented hooks into the caller's own code
(the matcher's profiling clock and map observer): a function named with
--hook may call through a pointer; the call is listed, and the caller
adds its hook's own depth to the bound (the library cannot know it).
A call through a pointer to the library's own functions (the matcher's
row-band jobs, handed to the caller's executor and back) is followed when
--edge names its possible targets: CALLER's pointer call then counts as a
call to each listed CALLEE.
Exit 1 when the deepest chain exceeds --max.
"""
import os
import re
import sys

NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
FRAME = re.compile(r'\\n(\d+) bytes \(([a-z,]+)\)')


def load(paths):
    frames, kinds, calls = {}, {}, {}
    files = []
    for p in paths:
        if os.path.isdir(p):
            for root, _, names in os.walk(p):
                files += [os.path.join(root, n) for n in names if n.endswith('.ci')]
        else:
            files.append(p)
    for f in sorted(files):
        text = open(f, encoding='utf-8', errors='replace').read()
        for title, label in NODE.findall(text):
            m = FRAME.search(label)
            if m:
                frames[title] = int(m.group(1))
                kinds[title] = m.group(2)
        for src, dst in EDGE.findall(text):
            calls.setdefault(src, set()).add(dst)
    return files, frames, kinds, calls


def main(argv):
    limit = None
    hooks = set()
    edges = {}
    args = argv[1:]
    while len(args) >= 2 and args[0] in ('--max', '--hook', '--edge'):
        if args[0] == '--max':
            limit = int(args[1])
        elif args[0] == '--hook':
            hooks.add(args[1])
        else:
            caller, _, targets = args[1].partition('=')
            edges.setdefault(caller, []).extend(t for t in targets.split(',') if t)
        args = args[2:]
    if not args:
        print(__doc__)
        return 2
    files, frames, kinds, calls = load(args)
    if not frames:
        print('stack_report: no frame records found (build with -fcallgraph-info=su)')
        return 2
    problems = []
    for fn, kind in kinds.items():
        if kind != 'static':
            problems.append(f'{fn}: frame is {kind}')
    memo = {}
    hook_calls = set()
    by_short = {}
    for title in frames:
        by_short.setdefault(title.rsplit(':', 1)[-1], []).append(title)
    for caller, targets in edges.items():
        for t in targets:
            if t not in by_short:
                problems.append(f'--edge {caller}={t}: no such function')

    def depth(fn, path):
        if fn in path:
            problems.append('recursion: ' + ' -> '.join(path + [fn]))
            return 0, [fn]
        if fn in memo:
            return memo[fn]
        best, chain = 0, []
        for callee in sorted(calls.get(fn, ())):
            if callee == '__indirect_call':
                short = fn.rsplit(':', 1)[-1]
                if short in hooks:
                    hook_calls.add(fn)
                if short in edges:
                    for t in edges[short]:
                        for title in by_short.get(t, ()):
                            d, c = depth(title, path + [fn])
                            if d > best:
                                best, chain = d, c
                elif short not in hooks:
                    problems.append(f'{fn}: indirect call')
                continue
            d, c = depth(callee, path + [fn])
            if d > best:
                best, chain = d, c
        result = (frames.get(fn, 0) + best, [fn] + chain)
        memo[fn] = result
        return result

    results = sorted(((depth(fn, [])[0], fn) for fn in frames), reverse=True)
    print(f'{len(files)} call-graph files, {len(frames)} functions')
    print('deepest entry points (bytes, chain):')
    for d, fn in results[:6]:
        chain = memo[fn][1]
        print(f'  {d:6d}  ' + ' -> '.join(f'{c}({frames.get(c, 0)})' for c in chain))
    worst = results[0][0]
    for h in sorted(hook_calls):
        print(f'  caller hook called from {h} (add the hook\'s own depth)')
    for p in sorted(set(problems)):
        print('  problem:', p)
    if limit is not None:
        verdict = 'within' if worst <= limit else 'OVER'
        print(f'worst case {worst} bytes, {verdict} the {limit}-byte bound')
        if worst > limit:
            return 1
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main(sys.argv))

#!/usr/bin/python3
"""docs_blocks.py OUTDIR FILE...: writes each fenced block of FILEs whose info string is
`sh runnable` to OUTDIR/NN.sh (in the files' order) and prints, per block, `OUTDIR/NN.sh FILE:LINE`.
A block left open at the end of a file is an error. Used by test_docs.sh (docs/testing.md)."""
import os
import re
import sys

OPEN = re.compile(r'^```sh[ \t]+runnable[ \t]*$')


def main():
    out, files = sys.argv[1], sys.argv[2:]
    n = 0
    for path in files:
        block, start = None, 0
        for i, line in enumerate(open(path, encoding='utf-8').read().split('\n'), 1):
            if block is None:
                if OPEN.match(line):
                    block, start = [], i
            elif line.strip() == '```':
                n += 1
                name = os.path.join(out, '%02d.sh' % n)
                with open(name, 'w', encoding='utf-8') as f:
                    f.write('# %s:%d\n' % (path, start) + '\n'.join(block) + '\n')
                print(name, '%s:%d' % (path, start))
                block = None
            else:
                block.append(line)
        if block is not None:
            sys.exit('%s:%d: a runnable block is not closed' % (path, start))


if __name__ == '__main__':
    main()

"""Shared start of the generated-walk tests (test_*.py beside this file):
the command line NEGOBS_SYNTH NEGOBS_PNG WORKDIR and a fresh WORKDIR."""
import os
import shutil
import sys


def setup(doc):
    """(synth, png, work) from sys.argv with WORKDIR emptied, or None after
    printing the usage line (the last line of the caller's doc string)."""
    if len(sys.argv) != 4:
        print(doc.strip().splitlines()[-1], file=sys.stderr)
        return None
    synth, png, work = sys.argv[1:]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    return synth, png, work

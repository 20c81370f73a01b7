# A stand-in for the few torch names run_fvvdp.py uses (tests/cli/test_security.sh).
import contextlib

float32 = "float32"


def device(name):
    return name


def no_grad():
    return contextlib.nullcontext()


def tensor(value, dtype=None):
    return value

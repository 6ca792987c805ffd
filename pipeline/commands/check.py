"""rvsweep check (not implemented yet)."""
from ..errors import UserError

HELP = "check (not implemented yet)"


def add_arguments(parser):
    pass


def run(args):
    raise UserError("'check' is not implemented yet")

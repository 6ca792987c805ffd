"""rvsweep bench (not implemented yet)."""
from ..errors import UserError

HELP = "bench (not implemented yet)"


def add_arguments(parser):
    pass


def run(args):
    raise UserError("'bench' is not implemented yet")

"""rvsweep sweep (not implemented yet)."""
from ..errors import UserError

HELP = "sweep (not implemented yet)"


def add_arguments(parser):
    pass


def run(args):
    raise UserError("'sweep' is not implemented yet")

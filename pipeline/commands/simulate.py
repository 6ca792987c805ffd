"""rvsweep simulate (not implemented yet)."""
from ..errors import UserError

HELP = "simulate (not implemented yet)"


def add_arguments(parser):
    pass


def run(args):
    raise UserError("'simulate' is not implemented yet")

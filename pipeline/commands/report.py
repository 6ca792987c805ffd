"""rvsweep report (not implemented yet)."""
from ..errors import UserError

HELP = "report (not implemented yet)"


def add_arguments(parser):
    pass


def run(args):
    raise UserError("'report' is not implemented yet")

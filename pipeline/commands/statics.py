"""rvsweep statics (not implemented yet)."""
from ..errors import UserError

HELP = "statics (not implemented yet)"


def add_arguments(parser):
    pass


def run(args):
    raise UserError("'statics' is not implemented yet")

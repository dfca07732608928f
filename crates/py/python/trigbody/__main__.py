"""``python -m trigbody ARGS``: the trigbody command line itself (the same
Rust parser and commands as the ``trigbody`` binary)."""

import sys

from . import cli

if __name__ == "__main__":
    sys.exit(cli(sys.argv[1:]))

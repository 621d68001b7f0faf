"""The ``audit`` console script: the same command line as the Rust binary,
run inside the extension on ``sys.argv``."""

import sys

from . import _native


def main() -> None:
    """Run ``audit`` with this process's arguments and exit with its code."""
    sys.stdout.flush()
    sys.stderr.flush()
    sys.exit(_native._cli_main(["audit", *sys.argv[1:]]))


if __name__ == "__main__":
    main()

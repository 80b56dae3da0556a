"""The `mps2p` command's entry point, kept outside the package: importing
mps2p loads libmps2p, and a library that cannot be found or loaded should
cost the user one line of advice, not a traceback."""
import sys


def main(argv=None):
    try:
        from mps2p.tools.cli import main as command
    except ImportError as e:  # no library, no header, or a missing dependency
        print("mps2p: %s" % e, file=sys.stderr)
        return 2
    return command(argv)


if __name__ == "__main__":
    sys.exit(main())

"""python3 -m rockwatch [--version]: the installed module's version, or what it offers."""
import argparse
import sys

import rockwatch


def main(argv=None):
    parser = argparse.ArgumentParser(prog="python3 -m rockwatch",
                                     description="rockwatch Python module (import rockwatch)")
    parser.add_argument("--version", action="store_true", help="print the module's version and exit")
    args = parser.parse_args(argv)
    if args.version:
        print(f"rockwatch {rockwatch.__version__}")
        return 0
    names = sorted(n for n in dir(rockwatch) if not n.startswith("_") and n != "rockwatch")
    print(f"rockwatch {rockwatch.__version__}: " + ", ".join(names))
    return 0


if __name__ == "__main__":
    sys.exit(main())

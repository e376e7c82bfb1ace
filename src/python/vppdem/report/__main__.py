"""python3 -m vppdem.report NAME ARGS...: runs the report NAME (vppdem.report.REPORTS) with its
arguments; without a name (or with -h) prints the reports, exit 2 on an unknown one."""
import importlib
import sys

from . import REPORTS


def usage():
    lines = ["usage: python3 -m vppdem.report NAME ARGS...   (NAME --help: its arguments)", "", "reports:"]
    lines += [f"  {name:16s} {what}" for name, (_, what) in REPORTS.items()]
    return "\n".join(lines)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else list(argv)
    if not argv or argv[0] in ("-h", "--help"):
        print(usage())
        return 0 if argv else 2
    name, args = argv[0], argv[1:]
    if name not in REPORTS:
        print(f"vppdem.report: unknown report '{name}'\n{usage()}", file=sys.stderr)
        return 2
    module = importlib.import_module(f".{REPORTS[name][0]}", __package__)
    # The report's messages and argparse name it as `vppdem.report NAME`.
    sys.argv = [f"vppdem.report {name}"] + args
    if args in (["-h"], ["--help"]) and not hasattr(module, "argparse"):
        print((module.__doc__ or "").strip())  # a report without argparse: its docstring is its usage
        return 0
    r = module.main(args)
    return r if isinstance(r, int) else 0


if __name__ == "__main__":
    sys.exit(main())

"""`python3 -m granflow COMMAND ...`: the package's commands (docs/python.md).

Commands:
  export   frames of a trajectory to a GSD file (HOOMD-blue's format) for OVITO, freud, MDAnalysis

`python3 -m granflow COMMAND --help` describes each command."""
import sys

COMMANDS = {
    "export": "frames of a trajectory to a GSD file (HOOMD-blue's format) for OVITO, freud and MDAnalysis",
}


def usage():
    lines = ["usage: python3 -m granflow COMMAND [ARGS...]", "", "commands:"]
    lines += [f"  {name:<8} {what}" for name, what in COMMANDS.items()]
    lines += ["", "python3 -m granflow COMMAND --help describes a command's options (docs/python.md)."]
    return "\n".join(lines)


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if not argv:
        print(usage(), file=sys.stderr)
        return 2
    if argv[0] in ("-h", "--help"):
        print(usage())
        return 0
    command, rest = argv[0], argv[1:]
    if command == "export":
        from granflow.export import main as export

        return export(rest)
    print(f"granflow: error: unknown command '{command}' (commands: {', '.join(COMMANDS)})", file=sys.stderr)
    return 2


if __name__ == "__main__":
    sys.exit(main())

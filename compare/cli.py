"""The command line: `python -m compare <command>`; each command lives in its own module.

A command module (compare/commands/) has a docstring (its first paragraph is the help line),
`add_arguments(parser)` and `main(args) -> int` (the exit status: 0 ok, 1 outside tolerance, 2
bad input). A group of commands (`tools`, the developer tools) is a package under
compare/commands/ whose __init__ holds SUBCOMMANDS, a name -> module table like COMMANDS below,
and METAVAR, the word its help uses for one of them. A command reports bad input by raising
SceneError or BadInput: `main` below turns either into one line on stderr and exit status 2,
before anything is written.

The tree is lazy: only the module of the command named on the command line is imported (with
its group's package), and only it declares its arguments; the others' help lines are read from
their docstrings without importing them, and only when a list of commands is printed (`--help`,
a mistyped or missing name). A command module's own imports stay light where it can (heavy ones
inside `main`), so that its `--help` starts fast too.
"""
from __future__ import annotations

import argparse
import ast
import importlib
import importlib.util
import os
import sys
import tokenize

COMMANDS = {   # python -m compare COMMAND, in the order --help lists them
    "list": "compare.commands.list_scenes",
    "run": "compare.commands.run",
    "validate": "compare.commands.validate",
    "identify": "compare.commands.identify",
    "mjcf": "compare.commands.mjcf",
    "scene": "compare.commands.scene",
    "sweep": "compare.commands.sweep",
    "bench": "compare.commands.bench",
    "play": "compare.commands.play",
    "calibrate": "compare.commands.calibrate",
    "solref": "compare.commands.solref",
    "attribute": "compare.commands.attribute",
    "study": "compare.commands.study",
    "tools": "compare.commands.tools",   # a group: python -m compare tools TOOL (its SUBCOMMANDS)
}

EXIT_OK, EXIT_TOLERANCE, EXIT_BAD_INPUT = 0, 1, 2
EXIT_INTERRUPTED = 130   # Ctrl-C, as a shell reports a process stopped by SIGINT
EXIT_BROKEN_PIPE = 141   # the reader of stdout went away (`| head`), as a shell reports SIGPIPE


def summary(doc: str | None) -> str:
    """A command's help line: the first paragraph of its module's docstring."""
    return " ".join((doc or "").strip().split("\n\n")[0].split())


def _docstring(module_name: str) -> str | None:
    """A module's docstring, read from its source without importing it (its imports may be
    heavy): the first token, when it is a string."""
    origin = importlib.util.find_spec(module_name).origin
    with open(origin, "rb") as f:
        for token in tokenize.tokenize(f.readline):
            if token.type in (tokenize.ENCODING, tokenize.NL, tokenize.NEWLINE, tokenize.COMMENT):
                continue
            if token.type == tokenize.STRING:
                return ast.literal_eval(token.string)
            return None
    return None


def _chosen(argv: list[str], names) -> tuple[str | None, int]:
    """The command argv names at this level and its index: the first word that is not an
    option; None when help comes first, or the word names no command (argparse then lists them)."""
    for i, word in enumerate(argv):
        if word in ("-h", "--help"):
            return None, i
        if not word.startswith("-"):
            return (word if word in names else None), i
    return None, len(argv)


def _add_commands(parser, commands: dict[str, str], argv: list[str], words: list[str], everything: bool,
                  metavar: str = "COMMAND") -> None:
    sub = parser.add_subparsers(dest="command" if not words else metavar.lower(), metavar=metavar, required=True)
    chosen, at = (None, 0) if everything else _chosen(argv, commands)
    for name, module_name in commands.items():
        if everything or name == chosen:
            module = importlib.import_module(module_name)
            p = sub.add_parser(name, help=summary(module.__doc__), description=module.__doc__,
                               formatter_class=argparse.RawDescriptionHelpFormatter)
            if is_group(module_name):
                _add_commands(p, module.SUBCOMMANDS, argv[at + 1:], [*words, name], everything,
                              getattr(module, "METAVAR", "COMMAND"))
            else:
                module.add_arguments(p)
                p.set_defaults(_main=module.main, _words=" ".join([*words, name]))
        elif chosen is None:   # a list of the commands is printed: their help lines, nothing imported
            sub.add_parser(name, help=summary(_docstring(module_name)))


def build_parser(argv: list[str] | None = None, everything: bool = False) -> argparse.ArgumentParser:
    """The parser for argv: the command it names declared in full (its module imported), the
    others by name and help line only. everything=True: every command and tool in full."""
    parser = argparse.ArgumentParser(
        prog="python -m compare",
        description="Compare a hand-written 2D contact simulator with its MuJoCo twin.")
    _add_commands(parser, COMMANDS, list(sys.argv[1:] if argv is None else argv), [], everything)
    return parser


def is_group(module_name: str) -> bool:
    """A group of commands is a package under compare/commands/ (its __init__ holds SUBCOMMANDS);
    a command is a module."""
    return importlib.util.find_spec(module_name).submodule_search_locations is not None


def command_tree(commands: dict[str, str] | None = None, words: tuple[str, ...] = ()):
    """Every command and group as its words on the command line: ("list",), ..., ("tools",),
    ("tools", "mutation"), ... (imports only the groups' packages)."""
    for name, module_name in (COMMANDS if commands is None else commands).items():
        yield (*words, name)
        if is_group(module_name):
            yield from command_tree(importlib.import_module(module_name).SUBCOMMANDS, (*words, name))


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    args = build_parser(argv).parse_args(argv)
    from scene_types import BadInput, SceneError

    try:
        status = args._main(args)
        sys.stdout.flush()   # a reader gone shows here, not as a traceback at the interpreter's exit
        return status
    except BrokenPipeError:
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())   # nothing more to say
        return EXIT_BROKEN_PIPE
    except KeyboardInterrupt:
        print(f"interrupted: python -m compare {args._words} stopped (Ctrl-C)", file=sys.stderr)
        return EXIT_INTERRUPTED
    except (SceneError, BadInput) as exc:
        details = getattr(exc, "details", "")  # a user's simulator raised: its own frames, once
        if details:
            print(details, file=sys.stderr)
        print(f"error: {exc}", file=sys.stderr)
        return EXIT_BAD_INPUT

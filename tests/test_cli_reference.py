"""docs/cli.md documents the command line the parser builds: every command, every
option and argument, every choice, and nothing the parser lacks.

The page has a section per command (``## `cspace inspect` ``), and one for the options
every command that reads a robot shares (``## Reading a robot``), which a command's
section takes by linking to it. In a section, each option or argument is a list item
that starts with its spellings in backticks, then a colon and what it does:
``- `-j N`, `--jobs N`: ...``; an option of choices writes them in braces
(``--format {text,json}``), exactly the parser's. The parser is walked from
`cspace._cli.main.build_parser`, so a new option, command or choice without its line
on the page fails here, and so does a line for an option that is gone.
"""

from __future__ import annotations

import argparse
import re
from dataclasses import dataclass, field

import pytest

from cspace._cli.main import build_parser

from conftest import REPO

PAGE = REPO / "docs" / "cli.md"
SHARED = "Reading a robot"
"""The section of the options every command that reads a robot takes."""
SHARED_LINK = "(#reading-a-robot)"
"""How a command's section says it takes them."""
HELP = {"-h", "--help"}
MANY_CHOICES = 12
"""An option with more choices than this (``inspect --ignore``'s finding codes) names
them by a link to where they are listed, not one by one."""


@dataclass
class Item:
    """One list item of the page: an option or argument and what it does."""

    names: list[str]
    braces: set[str] | None
    text: str


@dataclass
class Section:
    """One ``##`` section of the page."""

    title: str
    body: str
    items: dict[str, Item] = field(default_factory=dict)


@dataclass(frozen=True)
class Command:
    """What the parser says of one command (or of ``cspace`` itself, named '')."""

    options: dict[str, argparse.Action]
    positionals: dict[str, argparse.Action]


def _sections() -> dict[str, Section]:
    text = PAGE.read_text(encoding="utf-8")
    text = re.sub(r"```.*?```", "", text, flags=re.DOTALL)  # the --help example
    sections: dict[str, Section] = {}
    for block in re.split(r"^## ", text, flags=re.MULTILINE)[1:]:
        title, _, body = block.partition("\n")
        section = Section(title.strip(), body)
        for item in re.split(r"\n(?=- )", body):
            head = re.match(r"- ((?:`[^`]+`(?:, )?)+)", item)
            if not item.startswith("- `") or head is None:
                continue
            tokens = re.findall(r"`([^`]+)`", head.group(1))
            braces = re.search(r"\{([^}]*)\}", head.group(1))
            names = [token.split()[0].removesuffix("...") for token in tokens]
            rest = " ".join(item[head.end() :].split())
            parsed = Item(names, set(braces.group(1).split(",")) if braces else None, rest)
            for name in names:
                assert name not in section.items, f"{title}: {name} has two lines"
                section.items[name] = parsed
        sections[section.title] = section
    return sections


def _command(parser: argparse.ArgumentParser) -> Command:
    options: dict[str, argparse.Action] = {}
    positionals: dict[str, argparse.Action] = {}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            continue
        if action.option_strings:
            options.update({s: action for s in action.option_strings if s not in HELP})
        else:
            positionals[str(action.metavar or action.dest.upper())] = action
    return Command(options, positionals)


def _commands() -> dict[str, Command]:
    """Each command's options and arguments, ``cspace`` itself as ''."""
    parser = build_parser()
    commands = {"": _command(parser)}
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                commands[name] = _command(sub)
    return commands


SECTIONS = _sections()
COMMANDS = _commands()


def _documented(command: str) -> dict[str, Item]:
    """The options and arguments the page gives ``command``, the shared ones included."""
    title = f"`cspace {command}`" if command else "`cspace`"
    assert title in SECTIONS, f"docs/cli.md has no section {title}"
    section = SECTIONS[title]
    items = dict(section.items)
    if SHARED_LINK in section.body:
        items.update(SECTIONS[SHARED].items)
    return items


def test_every_command_has_a_section_and_every_section_a_command() -> None:
    titles = {t for t in SECTIONS if t.startswith("`cspace")}
    assert titles == {"`cspace`"} | {f"`cspace {name}`" for name in COMMANDS if name}


@pytest.mark.parametrize("command", list(COMMANDS))
def test_the_page_names_exactly_the_parsers_options_and_arguments(command: str) -> None:
    parsed = COMMANDS[command]
    documented = _documented(command)
    wanted = set(parsed.options) | set(parsed.positionals) | (set() if command else HELP)
    missing = wanted - set(documented)
    assert not missing, f"cspace {command}: not on docs/cli.md: {sorted(missing)}"
    extra = set(documented) - wanted
    assert not extra, f"cspace {command}: on docs/cli.md, not in the parser: {sorted(extra)}"


@pytest.mark.parametrize("command", list(COMMANDS))
def test_each_option_says_what_it_does_and_lists_its_choices(command: str) -> None:
    parsed = COMMANDS[command]
    documented = _documented(command)
    for name, action in {**parsed.options, **parsed.positionals}.items():
        item = documented.get(name)
        if item is None:
            continue  # the test above names what is missing
        assert len(re.findall(r"[A-Za-z]{2,}", item.text)) >= 3, f"{name}: no meaning given"
        choices = {str(c) for c in action.choices or ()}
        if item.braces is not None:
            assert item.braces == choices, f"cspace {command} {name}: choices {choices}"
        if len(choices) > MANY_CHOICES:
            assert "](" in item.text, f"cspace {command} {name}: link to where the choices are"
        else:
            absent = {
                c
                for c in choices
                if not re.search(rf"(?<![\w-]){re.escape(c)}(?![\w-])", item.text)
            }
            assert item.braces is not None or not absent, f"cspace {command} {name}: {absent}"


def test_the_shared_options_are_those_of_every_command_that_reads_a_robot() -> None:
    """The shared section lists what each command linking to it has, no more, and a
    command with those options links to it rather than leaving them out."""
    shared = set(SECTIONS[SHARED].items)
    assert shared, "the page has no shared options"
    for command, parsed in COMMANDS.items():
        if shared <= set(parsed.options):
            title = f"`cspace {command}`"
            assert title in SECTIONS and SHARED_LINK in SECTIONS[title].body, command


def test_no_option_on_the_page_is_unknown_to_the_parser() -> None:
    """Every option the page writes in code is one the parser has: a code span that is
    an option (`` `--strict` ``), and what follows ``cspace`` in a command (examples)."""
    known = set(HELP)
    for parsed in COMMANDS.values():
        known |= set(parsed.options)
    text = PAGE.read_text(encoding="utf-8")
    code = re.findall(r"```.*?```", text, flags=re.DOTALL)
    spans = re.findall(r"`([^`]+)`", re.sub(r"```.*?```", "", text, flags=re.DOTALL))
    written = [s for s in spans if s.startswith("-")]
    for line in "\n".join([*code, *spans]).splitlines():
        written += [part.split("|")[0] for part in re.split(r"\bcspace\b", line)[1:]]
    named = {w for s in written for w in re.findall(r"(?<![\w-])(--?[A-Za-z][\w-]*)", s)}
    assert named, "no option found on the page"
    assert not named - known, sorted(named - known)

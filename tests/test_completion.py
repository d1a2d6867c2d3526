"""Shell completion: scripts from argcomplete, checked in real shells.

The bash, fish and zsh scripts are sourced in a real bash, fish and zsh and asked, as a
user's TAB asks, for commands, options and choices (in zsh, only the completion system's
``_describe``, which shows candidates interactively, is stood in for); zsh and fish also
check that their scripts parse. ``make test`` installs zsh and fish (Debian's packages);
a missing shell fails its tests with the command that installs it.
"""

from __future__ import annotations

import os
import shutil
import subprocess
from pathlib import Path

import pytest

from cspace.conventions import TOOLS

from conftest import REPO, cspace_command, run_cli


def _bash_complete(script: Path, line: str) -> list[str]:
    """What bash's completion of ``line`` (the cursor at its end) offers."""
    words = line.split(" ")
    program = (
        f"source {script}\n"
        f"COMP_LINE={line!r}; COMP_POINT=${{#COMP_LINE}}; COMP_TYPE=9\n"
        f"COMP_WORDS=({' '.join(repr(w) for w in words)}); COMP_CWORD={len(words) - 1}\n"
        "_python_argcomplete cspace\n"
        'printf "%s\\n" "${COMPREPLY[@]}"\n'
    )
    done = subprocess.run(
        ["bash", "--norc", "--noprofile", "-c", program],
        capture_output=True,
        text=True,
        env=_env(),
        timeout=60,
        check=True,
    )
    return [w.strip() for w in done.stdout.splitlines() if w.strip()]


@pytest.fixture(scope="session")
def bash_script(tmp_path_factory: pytest.TempPathFactory) -> Path:
    run = run_cli("completion", "bash")
    assert run.code == 0
    path = tmp_path_factory.mktemp("completion") / "cspace.bash"
    path.write_text(run.stdout)
    return path


def test_bash_completes_commands(bash_script: Path) -> None:
    assert _bash_complete(bash_script, "cspace ins") == ["inspect"]
    assert {"convert", "check", "completion"} <= set(_bash_complete(bash_script, "cspace c"))


def test_bash_completes_options_and_their_choices(bash_script: Path) -> None:
    assert "--hide-fixed" in _bash_complete(bash_script, "cspace inspect --h")
    choices = _bash_complete(bash_script, "cspace convert --from ")
    assert set(choices) == {*TOOLS, "named"}


def _shell(name: str) -> str:
    """The shell's path; ``make test`` installs zsh and fish, so a missing one fails."""
    found = shutil.which(name)
    if found is None:
        pytest.fail(f"{name} is not installed: `make test` installs it (apt-get install {name})")
    return found


def _env() -> dict[str, str]:
    folder = str(Path(cspace_command()[0]).parent)
    return {**os.environ, "PATH": folder + os.pathsep + os.environ.get("PATH", "")}


def test_fish_completes_commands_and_choices(tmp_path: Path) -> None:
    fish = _shell("fish")
    path = tmp_path / "cspace.fish"
    path.write_text(run_cli("completion", "fish").stdout)
    program = f'source {path}; complete -C "cspace ins"; complete -C "cspace convert --to "'
    done = subprocess.run(
        [fish, "--no-config", "-c", program],
        capture_output=True, text=True, env=_env(), timeout=60, check=True,
    )  # fmt: skip
    offered = [line.split("\t")[0] for line in done.stdout.splitlines()]
    assert offered == ["inspect", *sorted({*TOOLS, "named"})]


@pytest.mark.parametrize("shell", ["zsh", "fish"])
def test_zsh_and_fish_scripts_parse(shell: str, tmp_path: Path) -> None:
    run = run_cli("completion", shell)
    assert run.code == 0 and "cspace" in run.stdout
    program = _shell(shell)
    path = tmp_path / f"cspace.{shell}"
    path.write_text(run.stdout)
    check = [program, "-n", str(path)] if shell == "zsh" else [program, "--no-execute", str(path)]
    subprocess.run(check, check=True, timeout=60)


def test_zsh_completes_commands_and_choices(tmp_path: Path) -> None:
    """The zsh script's own function, run by zsh: only zsh's ``_describe`` (which shows
    candidates in an interactive shell) and ``compdef`` are stood in for, to print them."""
    zsh = _shell("zsh")
    path = tmp_path / "cspace.zsh"
    path.write_text(run_cli("completion", "zsh").stdout)

    def complete(line: str) -> list[str]:
        words = " ".join(repr(w) for w in line.split(" "))
        program = (
            "autoload -U is-at-least\n"
            '_describe() { local name=$2; print -l -- "${(@P)name}" }\n'
            "compdef() { : }\n"
            f"source {path}\n"
            f"words=({words}); CURRENT={len(line.split(' '))}\n"
            f"BUFFER={line!r}; CURSOR=${{#BUFFER}}\n"
            "_python_argcomplete\n"
        )
        done = subprocess.run(
            [zsh, "-f", "-c", program],
            capture_output=True, text=True, env=_env(), timeout=60, check=True,
        )  # fmt: skip
        return [entry.split(":")[0] for entry in done.stdout.splitlines()]

    assert complete("cspace ins") == ["inspect"]
    assert set(complete("cspace unwrap --convention ")) == set(TOOLS)


def _readme_install_lines() -> list[str]:
    """The documentation's completion install block, as a user copies it."""
    text = (REPO / "docs" / "getting-started.md").read_text()
    block = text.split("# bash (with the bash-completion package", 1)[1].split("```", 1)[0]
    return [line for line in block.splitlines()[1:] if line and not line.startswith("#")]


def test_the_documented_install_lines_work_on_a_fresh_account(tmp_path: Path) -> None:
    # ~/.zfunc, ~/.config/fish/completions and bash-completion's folder do not exist on
    # a new account: the lines make them
    home = tmp_path / "home"
    home.mkdir()
    env = {**_env(), "HOME": str(home)}
    env["PATH"] = f"{Path(cspace_command()[0]).parent}{os.pathsep}{env.get('PATH', '')}"
    for line in _readme_install_lines():
        done = subprocess.run(["sh", "-c", line], env=env, capture_output=True, text=True)
        assert done.returncode == 0, (line, done.stderr)
    bash = home / ".local/share/bash-completion/completions/cspace"
    assert subprocess.run(["bash", "-n", str(bash)], check=False).returncode == 0
    zsh = home / ".zfunc/_cspace"
    assert zsh.read_text().startswith("#compdef cspace")
    if shutil.which("fish"):  # fish loads ~/.config/fish/completions by itself
        offered = subprocess.run(
            ["fish", "-c", "complete -C 'cspace ins'"],
            env=env,
            capture_output=True,
            text=True,
            timeout=60,
            check=True,
        )
        assert offered.stdout.split()[0] == "inspect", offered.stdout

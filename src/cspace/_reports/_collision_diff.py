"""Two collisions reports of one robot, pair by pair: what a baseline check holds it to.

`diff_collisions` takes the accepted report (a baseline's line, checked as a saved
collisions report is) and the report drawn again now with the same ``samples`` and
``seed``, and says what changed:

- ``changed`` when the matrix a planner works with differs: the file that says which
  pairs are checked (``matrix``: ``srdf``, ``mjcf``, ``usd``, ``none``; for ``srdf``, the
  SRDF's place beside the robot file too, so that an SRDF that ``--srdf auto`` finds
  first, added beside the robot, cannot stand in for the one accepted), a pair added or
  gone (a link renamed, removed, given or stripped of its shapes), a pair's class
  (MoveIt's ``adjacent``, ``default``, ``always``, ``never``, ``sometimes``), a pair's
  rule (checked or not, or no file saying), or an error finding that the accepted report
  does not have (by its code and the names it quotes);
- ``differs`` when the classes and rules are the same but a pair's share of samples in
  collision (or the share free of self-collision) moved out of the 95% interval the
  robot gives now: its collision geometry changed measurably (with the same samples an
  unchanged robot gives the same counts);
- ``same`` otherwise: counts that moved within that interval are not a change.

Only the report drawn now is trusted: the accepted one gives names, classes, rules and
counts to compare with, never an interval (the interval is the new report's) nor a file
to read. Pure: documents in, changes out (an SRDF's place is read from the current
folder when a report gives one path relative and the other absolute).
"""

import os
import re
from collections.abc import Mapping, Sequence
from typing import Any

from cspace._record import NamedTuple

CHANGED_KINDS = ("matrix", "pair added", "pair gone", "class", "rule", "error")
"""The kinds of `CollisionChange` that make a check ``changed``, in the order listed."""

DIFFERS_KINDS = ("share", "free share")
"""The kinds that make it ``differs`` (when none of `CHANGED_KINDS` is there)."""

_QUOTED = re.compile(r"'([^']*)'")


class CollisionChange(NamedTuple):
    """One difference between the accepted collisions report and the robot's now.

    Attributes:
        kind: One of `CHANGED_KINDS` or `DIFFERS_KINDS`.
        pair: The link pair ``(link1, link2)``, names sorted, or None (the matrix, the
            free share, an error that names no pair).
        before: What the accepted report says, in words (``-``: nothing).
        after: What the robot gives now (``-``: nothing).
        line: The line that says it now: the pair's rule's (an SRDF's
            ``<disable_collisions>``, MuJoCo's filter), the finding's, or None.
        file: The file of ``line`` when it is not the robot file (the SRDF), or None.
    """

    kind: str
    pair: tuple[str, str] | None
    before: str
    after: str
    line: int | None = None
    file: str | None = None

    @property
    def text(self) -> str:
        """The change in a few words: ``'a'-'b' class never -> sometimes``."""
        who = "" if self.pair is None else f"'{self.pair[0]}'-'{self.pair[1]}' "
        if self.kind == "pair added":
            return f"{who}new pair ({self.after})"
        if self.kind == "pair gone":
            return f"{who}gone (was {self.before})"
        if self.kind == "error":
            return f"new error {self.after}"
        return f"{who}{self.kind} {self.before} -> {self.after}"


class CollisionDiff(NamedTuple):
    """The verdict of two collisions reports of one robot, and its changes.

    Attributes:
        verdict: ``same``, ``differs`` or ``changed`` (see the module).
        changes: The changes, ``changed``'s kinds first, each kind by pair; for
            ``same``, none.
        pairs: The pairs of the report drawn now.
        samples: The samples drawn (the accepted report's).
        seed: Their seed.
    """

    verdict: str
    changes: tuple[CollisionChange, ...]
    pairs: int
    samples: int
    seed: int


def diff_collisions(accepted: Mapping[str, Any], now: Mapping[str, Any]) -> CollisionDiff:
    """What changed from the ``accepted`` collisions document to the one drawn ``now``.

    Args:
        accepted: The accepted report's JSON document (checked as a saved collisions
            report is: `check_collisions_document`).
        now: The robot's report now (`CollisionReport.to_dict`), drawn with the
            accepted report's ``samples`` and ``seed``.

    Returns:
        The verdict and its changes (see the module).
    """
    old = {(p["link1"], p["link2"]): p for p in accepted["pairs"]}
    new = {(p["link1"], p["link2"]): p for p in now["pairs"]}
    changes: list[CollisionChange] = []
    if accepted["matrix"] != now["matrix"]:
        changes.append(CollisionChange("matrix", None, accepted["matrix"], now["matrix"]))
    elif accepted["matrix"] == "srdf" and _srdf_place(accepted) != _srdf_place(now):
        before, after = (f"srdf {_srdf_place(d)}" for d in (accepted, now))
        changes.append(CollisionChange("matrix", None, before, after))
    for pair in sorted(old.keys() | new.keys()):
        changes += _pair_changes(pair, old.get(pair), new.get(pair))
    changed = {c.pair for c in changes}
    changes += _new_errors(accepted["diagnostics"], now["diagnostics"], changed)
    if not changes and (accepted["samples"], accepted["seed"]) == (now["samples"], now["seed"]):
        changes += _moved(old, new, accepted["free"], now["free"])
    changes.sort(key=lambda c: (_ORDER.index(c.kind), c.pair or ("", "")))
    verdict = (
        "changed"
        if any(c.kind in CHANGED_KINDS for c in changes)
        else "differs"
        if changes
        else "same"
    )
    return CollisionDiff(verdict, tuple(changes), len(new), now["samples"], now["seed"])


_ORDER = (*CHANGED_KINDS, *DIFFERS_KINDS)


def _srdf_place(document: Mapping[str, Any]) -> str:
    """Where a report's SRDF is, from its robot file's folder: ``../srdf/ur5.srdf``.

    Each report wrote both paths from one folder; an ``erd:`` robot's is its name alone.
    """
    srdf, robot = str(document["srdf"]), str(document["source"]["path"])
    if robot.startswith("erd:"):
        return os.path.basename(srdf)
    return os.path.normpath(os.path.relpath(srdf, os.path.dirname(robot) or os.curdir))


def _where(pair: Mapping[str, Any] | None) -> tuple[int | None, str | None]:
    """The line (and its file) of the element that says what a pair's rule says, if any."""
    rule = None if pair is None else pair["rule"]
    if rule is None or rule["line"] is None:
        return None, None
    return rule["line"], rule.get("file")


def _rule(pair: Mapping[str, Any]) -> str:
    rule = pair["rule"]
    if rule is None:
        return "no file says"
    if rule["checked"]:
        return "checked"
    return f"disabled ({rule['reason']})" if rule["reason"] else "disabled"


def _checked(pair: Mapping[str, Any]) -> bool | None:
    """Whether the pair's file checks it (None: no file says)."""
    rule = pair["rule"]
    return None if rule is None else bool(rule["checked"])


def _pair_changes(
    pair: tuple[str, str], old: Mapping[str, Any] | None, new: Mapping[str, Any] | None
) -> list[CollisionChange]:
    """A pair's changes; its line is where the robot's files say of it now (or None)."""
    line, file = _where(new)
    if new is None:
        return [] if old is None else [CollisionChange("pair gone", pair, old["kind"], "-")]
    if old is None:
        return [CollisionChange("pair added", pair, "-", new["kind"], line, file)]
    out = []
    if old["kind"] != new["kind"]:
        out.append(CollisionChange("class", pair, old["kind"], new["kind"], line, file))
    if _checked(old) != _checked(new):
        out.append(CollisionChange("rule", pair, _rule(old), _rule(new), line, file))
    return out


def _error_key(diagnostic: Mapping[str, Any]) -> tuple[str, tuple[str, ...]]:
    """An error finding by its code and the names its message quotes (not its counts)."""
    return str(diagnostic["code"]), tuple(_QUOTED.findall(str(diagnostic["message"])))


def _new_errors(
    accepted: Sequence[Mapping[str, Any]],
    now: Sequence[Mapping[str, Any]],
    changed: set[tuple[str, str] | None],
) -> list[CollisionChange]:
    """The error findings of ``now`` the accepted report lacks.

    Those about a pair already changed are left out: a pair newly disabled is one
    change, not two.
    """
    known = {_error_key(d) for d in accepted if d["severity"] == "error"}
    out = []
    for d in now:
        key = _error_key(d)
        if d["severity"] != "error" or key in known:
            continue
        names = key[1]
        pair = (min(names[:2]), max(names[:2])) if len(names) >= 2 else None
        if pair is not None and pair in changed:
            continue
        after = f"{d['code']}: {d['message']}"
        out.append(CollisionChange("error", pair, "-", after, d.get("line"), d.get("file")))
    return out


def _percent(share: Mapping[str, Any]) -> str:
    return f"{100 * share['hits'] / share['samples']:.2f}%"


def _outside(old: Mapping[str, Any] | None, new: Mapping[str, Any] | None) -> bool:
    """Whether the accepted share lies outside the 95% interval the robot gives now."""
    if old is None or new is None:
        return False
    return not new["low"] <= old["hits"] / old["samples"] <= new["high"]


def _after(share: Mapping[str, Any]) -> str:
    """A share drawn now, with its interval: ``9.00% (95% interval 7.10-11.20%)``."""
    low, high = 100 * share["low"], 100 * share["high"]
    return f"{_percent(share)} (95% interval {low:.2f}-{high:.2f}%)"


def _moved(
    old: Mapping[tuple[str, str], Mapping[str, Any]],
    new: Mapping[tuple[str, str], Mapping[str, Any]],
    old_free: Mapping[str, Any],
    new_free: Mapping[str, Any],
) -> list[CollisionChange]:
    """The shares (of the same pairs, in the same classes) that moved measurably."""
    out = []
    for pair, p in sorted(new.items()):
        before, after = old[pair]["collisions"], p["collisions"]
        if _outside(before, after):
            line, file = _where(p)
            text = _percent(before)
            out.append(CollisionChange("share", pair, text, _after(after), line, file))
    if _outside(old_free, new_free):
        out.append(CollisionChange("free share", None, _percent(old_free), _after(new_free)))
    return out

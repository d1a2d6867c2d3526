"""``cspace check --baseline FILE ROBOTS...``: each robot against its accepted report.

One line per robot (text), a table (Markdown) or workflow commands (``github``):
``same`` when its C-space is the baseline's, ``changed`` when the C-space changed,
``differs`` when only its limits or q/v layout differ (or it is read with another
joint_limits.yaml than its accepted report, or with none), ``new`` when the baseline has no
report of it, ``moved`` when a file renamed has the report of one the baseline holds
and that is gone (this passes); a line for each other baseline report whose file is
gone; and ``outside`` for a report of a file outside the folders checked (see
`.baseline_scope`), which is never read: it changes no robot's verdict, so it passes,
and in the ``github`` format it is a ``warning`` on the baseline's line. A file the
baseline holds in a folder named is read whatever the folder's search found there
(`Place.path`, through the one way in: a link cspace follows only within its folder);
one behind a link out of the folders checked is not read and has no report. Every file
is read as a robot description, never as a saved report (a JSON file has no report),
and is compared with the report of its own path: nothing a file says picks the
baseline's report it is compared with. In the
``github`` format each difference is an ``error`` annotation at the joint's line in
the new file (at the file for what belongs to the whole robot), so a reviewer sees it
where the pull request changed it. A robot whose baseline holds a collisions report too
(``cspace collisions --format jsonl``) gets a second row, its self-collision matrix drawn
again and compared (`.baseline_collisions`). Exit 0 when all are the same or moved, 1
when any differs, 2 when a robot gives no report or the baseline cannot be read.
"""

from __future__ import annotations

import argparse
import os
from collections.abc import Mapping
from typing import TYPE_CHECKING, Any

import cspace
from cspace._render import formats
from cspace._reports.baseline import Row, Spot

from . import exit_codes, output
from .baseline_scope import FILE, HIDDEN, LINKED, OUTSIDE, ROBOT_NAME, VCS, Place, Scope
from .patterns import Searched
from .robots import expand_patterns, load_document, refuses_xacro_options

if TYPE_CHECKING:
    from cspace._reports.baseline import Baseline, Entry
    from cspace._reports.diff import ReportDiff


_NOT_READ = {
    OUTSIDE: ("outside the folders checked", "check its folder"),
    HIDDEN: ("hidden (a name starting with '.')", "name the file"),
    VCS: ("hidden (a link among its folders leads into .git, .hg or .svn)", "remove the link"),
    ROBOT_NAME: ("not among the robots checked", "name the robot"),
    LINKED: ("behind a link out of the folders checked", "check its folder"),
}
"""Why a baseline report was not compared, by where its file lies, and what else to do
than remove its line."""


def check_baseline(args: argparse.Namespace) -> int:
    """Compare each robot named with the baseline's report of it."""
    from cspace._reports.baseline import read_baseline

    if refuses_xacro_options(args):
        return exit_codes.NO_REPORT
    scope = Scope(args.robot)
    check = _Check(read_baseline(args.baseline, scope.key), scope, args)
    for name in expand_patterns(args.robot):
        check.robot(name)
    # A baselined file in a folder named that no file read so far was (the folder's
    # search left it out: a robot turned fragment, no longer XML, a link) is read too.
    for key, entry in sorted({**check.collisions, **check.baseline}.items()):
        place = scope.place(entry.path)
        if place.walked and key not in check.read:
            if place.where == FILE and place.exists:
                check.robot(place.path)
            elif place.where == LINKED:
                check.unread(place)
    check.gone()
    check.collisions_left()
    check.not_read(args.baseline)
    write = output.write_commands if formats.FORMATS[args.format].commands else output.write
    write(formats.check(args.format, check.rows, formats.Options()))
    return check.worst


class _Check:
    """The rows of a run, the baseline's reports, and those of files gone."""

    def __init__(self, baseline: Baseline, scope: Scope, args: argparse.Namespace) -> None:
        self.baseline, self.scope, self.args = baseline.reports, scope, args
        self.collisions = baseline.collisions  # the accepted self-collision matrices
        self.drawn: set[str] = set()  # keys of the collisions reports compared (or gone)
        self.moved: dict[str, str] = {}  # a gone file's key -> the robot it moved to
        self.rows: list[Row] = []
        self.checked: set[str] = set()  # keys of the files read and of the reports compared
        self.read: set[str] = set()  # keys of the files read
        self.worst = exit_codes.OK
        self.pending: list[tuple[int, Mapping[str, Any]]] = []  # new files that may have moved
        gone = []
        for key, entry in self.baseline.items():
            place = scope.place(entry.path)
            if place.where == FILE and not place.exists:
                gone.append(key)
        self.gone_by = _GoneFiles(self.baseline, gone)

    def robot(self, name: str) -> None:
        """Check one robot against the baseline's report of its own path.

        A file is read as a robot description only: a saved report (JSON) committed in
        a robot's place has no report, and no ``source.path`` in a file picks the
        baseline's report it is compared with.
        """
        named = self.scope.key(name)
        self.checked.add(named)
        self.read.add(named)
        if self._c_space(name, named) and named in self.collisions:
            self._draw(named, str(name), self.collisions[named])

    def _c_space(self, name: str, named: str) -> bool:
        """The robot's C-space row; whether it gave a report."""
        from cspace._formats.shared.roots import SRDF_CODE
        from cspace._reports.summary import FRAGMENT_CODE

        try:
            document = load_document(name, self.args, reports=False)
        except cspace.CspaceError as exc:
            code = getattr(exc, "code", None)
            if code in (FRAGMENT_CODE, SRDF_CODE) and (
                named in self.baseline or named in self.collisions
            ):
                now = "an MJCF fragment" if code == FRAGMENT_CODE else "an SRDF"
                self.drawn.add(named)
                self._fail(name, "gone", f"in the baseline, but now {now}, no robot")
            elif code == FRAGMENT_CODE or (code == SRDF_CODE and isinstance(name, Searched)):
                output.note(f"{exc} [{code}]")  # no robot of its own (an SRDF a search told)
            else:
                output.error(f"{exc} [{code}]" if isinstance(code, str) else str(exc))
                self._fail(name, "no report", str(exc), exit_codes.NO_REPORT)
            self.drawn.add(named)
            return False
        path = str(name)
        notation = str(document["manifold"]["notation"])
        entry = self.baseline.get(named)
        if entry is None:
            if self.gone_by.may_have(document):  # moved? decided once all are read
                self.pending.append((len(self.rows), document))
                self.rows.append(Row(path, "new", f"{notation}, not in the baseline"))
            else:
                self._fail(path, "new", f"{notation}, not in the baseline")
            return True
        diff = _compared(entry, document)
        if diff.verdict == "same":
            self.rows.append(Row(path, "same", notation))
            return True
        what = (
            f"{diff.old_manifold} -> {diff.new_manifold}: {diff.kinds_text}"
            if diff.changed
            else f"{notation}, but {diff.what_differs}"
        )
        self.rows.append(Row(path, diff.verdict, what, _spots(diff, document)))
        self.worst = max(self.worst, exit_codes.FINDINGS)
        return True

    def _draw(self, key: str, path: str, entry: Entry) -> None:
        """The robot's self-collision row against its accepted collisions report."""
        from .baseline_collisions import compared

        self.drawn.add(key)
        row, code = compared(path, entry, self.args)
        self.rows.append(row)
        self.worst = max(self.worst, code)

    def gone(self) -> None:
        """Files moved, new ones, and a row for each baseline report whose file is gone.

        New files are paired with gone ones in the order of their paths, whatever the
        order they were named in.
        """
        for index, document in sorted(self.pending, key=lambda p: self.rows[p[0]].path):
            row = self.rows[index]
            old = self.gone_by.moved_to(row.path, document)
            if old is None:
                self.rows[index] = Row(
                    row.path, row.verdict, row.what, (Spot(None, "new", row.what),)
                )
                self.worst = max(self.worst, exit_codes.FINDINGS)
            else:
                notation = document["manifold"]["notation"]
                self.rows[index] = Row(row.path, "moved", f"from {old}, the same {notation}")
                self.moved[old] = row.path
        for key in self.gone_by.left():
            if key not in self.read:
                self._fail(key, "gone", "in the baseline, but the file is gone")

    def collisions_left(self) -> None:
        """The collisions reports of files not read: moved, gone, or only looked for.

        A robot moved (its C-space row ``moved``) is compared with the collisions report
        of the file it moved from, unless the baseline holds one of its own. A file gone
        whose baseline holds no inspect report (which says ``gone`` already) is ``gone``.
        """
        for key, entry in self.collisions.items():
            if key in self.drawn:
                continue
            place = self.scope.place(entry.path)
            if place.where != FILE or place.exists:
                continue  # not read (below), or only looked for
            moved = self.moved.get(key)
            if moved is not None and self.scope.key(moved) not in self.collisions:
                self._draw(key, moved, entry)
            elif moved is None and key not in self.baseline:
                self.drawn.add(key)
                self._fail(
                    key, "gone", "its collisions report is in the baseline, but the file is gone"
                )

    def unread(self, place: Place) -> None:
        """A row for a baselined file whose path leads out of the folders checked.

        Through a link in them (a folder of its path): the file is not read, nor looked
        at past the link, so it has no report.
        """
        what = "a folder of its path is a link out of the folders checked: not read"
        output.error(f"{place.path}: {what} [outside-tree]")
        self.checked.add(place.key)
        self.read.add(place.key)
        self._fail(place.path, "no report", what, exit_codes.NO_REPORT)

    def not_read(self, baseline: str) -> None:
        """A row for each baseline report of a file not checked and not looked at.

        Outside the folders checked (or hidden in them, or a robot not named): the
        file is neither read nor looked for, so the row says the same
        whether it exists or not. It fails nothing; in the ``github`` format it is a
        warning on the baseline's line, for the line to be removed.
        """
        reports = [(k, e, "") for k, e in self.baseline.items()]
        reports += [(k, e, "its collisions report ") for k, e in self.collisions.items()]
        for key, entry, which in sorted(reports, key=lambda r: r[1].line):
            where = self.scope.place(entry.path).where
            if where == FILE or key in self.checked:
                continue
            why, hint = _NOT_READ[where]
            what = f"{which}in the baseline, but {why}: not read"
            message = f"{entry.path}: {what} (remove the line, or {hint})"
            spot = Spot(entry.line, "outside", message, "warning", baseline)
            self.rows.append(Row(entry.path, "outside", what, (spot,)))

    def _fail(self, path: str, verdict: str, what: str, code: int = exit_codes.FINDINGS) -> None:
        self.rows.append(Row(path, verdict, what, (Spot(None, verdict, what),)))
        self.worst = max(self.worst, code)


class _GoneFiles:
    """The baseline's reports of files that are gone, and the new files they moved to.

    A new file moved from a gone one when the two reports diff as the same. Candidates
    share a key (`_key`: what diffs compare, limits to 4 significant digits), each gone
    report read once for it; a new file diffs at most `_TRIES` of them (one of its own
    name first), so the pairing is linear in the files.
    """

    def __init__(self, baseline: Mapping[str, Entry], gone: list[str]) -> None:
        from cspace._reports.savedreport import read_report_document

        self.baseline = baseline
        self.by_key: dict[tuple[Any, ...], list[str]] = {}
        for path in sorted(gone):
            key = _key(read_report_document(baseline[path].where, baseline[path].data))
            self.by_key.setdefault(key, []).append(path)
        self.moved: set[str] = set()

    def may_have(self, document: Mapping[str, Any]) -> bool:
        """Whether a gone report shares ``document``'s key (it may have moved)."""
        return bool(self.by_key.get(_key(document)))

    def moved_to(self, path: str, document: Mapping[str, Any]) -> str | None:
        """The gone file ``path`` moved from (its report the same as ``document``), or None."""
        olds = self.by_key.get(_key(document), [])
        while olds and olds[0] in self.moved:  # those taken leave the front
            olds.pop(0)
        base = os.path.basename(path)
        named = [o for o in olds[: _TRIES * 4] if os.path.basename(o) == base]  # near the front
        tries = [*named, *(o for o in olds[:_TRIES] if o not in named)][:_TRIES]
        for old in tries:
            if old in self.moved:
                continue
            if _compared(self.baseline[old], document).verdict == "same":
                self.moved.add(old)
                return old
        return None

    def left(self) -> list[str]:
        """The gone files that did not move, in path order."""
        return sorted(p for ps in self.by_key.values() for p in ps if p not in self.moved)


_TRIES = 4
"""Most gone reports diffed with one new file (those of its own name first)."""


def _key(document: Mapping[str, Any]) -> tuple[Any, ...]:
    """What two reports that diff as the same share, near enough to find candidates.

    The C-space, and each counted joint's name, kind, space, place in q and v, and
    limits to 4 significant digits (a diff's tolerance is finer: two reports of one key
    may still differ, and a pair near a rounding edge may be missed, as new and gone).
    """

    def limits(j: Mapping[str, Any]) -> tuple[str, ...]:
        bounds = j.get("limits") or {}
        return tuple(
            f"{x:.4g}" if isinstance(x, float | int) else str(x)
            for x in (*bounds.get("lower", ()), *bounds.get("upper", ()))
        )

    return (
        document["manifold"]["notation"],
        *(
            (j["name"], j["kind"], j["manifold"], j.get("q_index"), j.get("v_index"), limits(j))
            for j in document["joints"]
            if j["nq"] or j["dimension"]
        ),
    )


def _limits_file(document: Mapping[str, Any]) -> str | None:
    """The joint_limits.yaml a report was read with, its path folded (no file looked at)."""
    summary = document.get("limits_file")
    if not summary:
        return None
    return os.path.abspath(os.path.normpath(str(summary["file"])))


def _compared(entry: Entry, document: Mapping[str, Any]) -> ReportDiff:
    """The diff of the baseline's accepted report and the robot's ``document``.

    With a ``limits`` change when the robot is read with another joint_limits.yaml:
    ``--limits auto`` reads the nearest of the robot's joint_limits.yaml: one added nearer
    (beside the URDF, holding the accepted values) would otherwise hide a change to the
    file MoveIt reads, and one read where the baseline read none, or none where it read
    one, is a change of what the check holds the robot to.
    """
    import dataclasses

    from cspace._reports._changes import CHANGE_KINDS, Change
    from cspace._reports.diff import diff_reports
    from cspace._reports.savedreport import read_report_document

    accepted = read_report_document(entry.where, entry.data)
    diff = diff_reports(accepted, document)
    was, now = ((d.get("limits_file") or {}).get("file") for d in (accepted, document))
    if _limits_file(accepted) == _limits_file(document):
        return diff
    change = Change(
        "limits",
        None,
        f"limits from {was}" if was else "no joint_limits.yaml read",
        f"limits from {now}" if now else "no joint_limits.yaml read",
    )
    changes = sorted((*diff.changes, change), key=lambda c: CHANGE_KINDS.index(c.kind))
    return dataclasses.replace(diff, changes=tuple(changes))


def _spots(diff: ReportDiff, document: Mapping[str, Any]) -> tuple[Spot, ...]:
    """Each change of a diff at its joint's line, or its loop cut's, in the new file."""
    from cspace._reports._closure_diff import cut_text
    from cspace._reports.closure import Cut
    from cspace._reports.diff import CHANGE_LABELS

    lines = {j["name"]: j.get("line") for j in document["joints"]}
    cuts = (document.get("closure") or {}).get("cuts", ())
    cut_lines = {cut_text(Cut.from_dict(cut)): cut.get("line") for cut in cuts}
    spots = []
    for c in diff.changes:
        if c.before == "-":
            said = f"{c.after}, not in the baseline"
        elif c.after == "-":
            said = f"{c.before} in the baseline, none now"
        else:
            said = f"{c.before} in the baseline, {c.after} now"
        line = lines.get(c.joint) if c.joint is not None else cut_lines.get(c.after)
        message = (
            f"{c.joint + ': ' if c.joint else ''}{said} (write the baseline again to accept it)"
        )
        spots.append(Spot(line, CHANGE_LABELS[c.kind], message))
    return tuple(spots)

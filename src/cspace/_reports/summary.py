"""One line per robot file, for ``cspace inspect`` given several files.

A row holds a report's headline (format, C-space, dimension, sizes, finding counts) or,
for a file that gave no report, the one-line error. Text and Markdown tables of rows;
rows hold raw values, which the renderers escape (`_safetext`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

from cspace._findings import Severity
from cspace._reports.report import Report

STATUS_OK = "ok"
STATUS_FINDINGS = "findings"
STATUS_NO_REPORT = "no report"
STATUS_FRAGMENT = "fragment"
FRAGMENT_CODE = "mjcf-fragment"
"""The code of the refusal of an MJCF fragment: a file left to the model including it."""


@dataclass(frozen=True)
class SummaryRow:
    """One robot file's line in the summary.

    Attributes:
        path: The file as given.
        status: ``ok``, ``findings`` (the file fails the check asked for) or ``no report``.
        format: ``urdf``, ``xacro``, ``mjcf`` or ``sdf``; None without a report.
        manifold: The C-space notation; None without a report.
        dimension: The dimension; None without a report.
        nq: Configuration vector length; None without a report.
        nv: Tangent vector length; None without a report.
        errors: Number of error findings.
        warnings: Number of warning findings.
        problem: Why there is no report (one line), or None.
        failing: The findings that fail the check asked for, each as (severity, line
            or None, code, message), in the report's order.
    """

    path: str
    status: str
    format: str | None = None
    manifold: str | None = None
    dimension: int | None = None
    nq: int | None = None
    nv: int | None = None
    errors: int = 0
    warnings: int = 0
    problem: str | None = None
    failing: tuple[tuple[str, int | None, str, str], ...] = ()

    @classmethod
    def of_report(cls, report: Report, failed: bool, strict: bool = False) -> SummaryRow:
        """The row of a report; ``failed`` when its findings fail the check asked for.

        Its errors fail it, and under ``strict`` its warnings too (`failing`).
        """
        failing = (Severity.ERROR, Severity.WARNING) if strict else (Severity.ERROR,)
        return cls(
            path=report.source.path,
            status=STATUS_FINDINGS if failed else STATUS_OK,
            format=report.source.format,
            manifold=report.manifold.notation,
            dimension=report.dimension,
            nq=report.nq,
            nv=report.nv,
            errors=sum(d.severity is Severity.ERROR for d in report.diagnostics),
            warnings=sum(d.severity is Severity.WARNING for d in report.diagnostics),
            failing=tuple(
                (d.severity.value, d.line, d.code, d.message)
                for d in report.diagnostics
                if failed and d.severity in failing
            ),
        )

    @classmethod
    def of_error(cls, path: str, problem: str) -> SummaryRow:
        """The row of a file that gave no report."""
        return cls(path=path, status=STATUS_NO_REPORT, problem=problem)

    @classmethod
    def of_fragment(cls, path: str) -> SummaryRow:
        """The row of an MJCF fragment, checked as part of the model that includes it."""
        return cls(path=path, status=STATUS_FRAGMENT, format="mjcf")

    def cells(self) -> list[str]:
        """path, format, C-space, dim, nq/nv, errors, warnings, status."""
        if self.problem is not None or self.status == STATUS_FRAGMENT:
            return [self.path, self.format or "-", "-", "-", "-", "-", "-", self.status]
        return [
            self.path,
            self.format or "-",
            self.manifold or "-",
            str(self.dimension),
            f"{self.nq}/{self.nv}",
            str(self.errors),
            str(self.warnings),
            self.status,
        ]


HEADER = ("robot", "format", "C-space", "dim", "nq/nv", "err", "warn", "status")


def totals(rows: Sequence[SummaryRow]) -> str:
    """The summary's last line: how many files ended in each way, and their findings."""
    counts = {
        s: sum(r.status == s for r in rows) for s in (STATUS_OK, STATUS_FINDINGS, STATUS_NO_REPORT)
    }
    errors, warnings = sum(r.errors for r in rows), sum(r.warnings for r in rows)
    fragments = sum(r.status == STATUS_FRAGMENT for r in rows)
    left = f", {fragments} MJCF fragments left to their models" if fragments else ""
    return (
        f"{len(rows)} robot files: {counts[STATUS_OK]} ok, {counts[STATUS_FINDINGS]} failing, "
        f"{counts[STATUS_NO_REPORT]} without a report{left}; {errors} error and {warnings} "
        "warning findings in all"
    )

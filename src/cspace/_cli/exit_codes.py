"""Exit codes of every `cspace` command."""

OK = 0
"""Report written; no error-level finding (nor a warning under ``--strict``)."""
FINDINGS = 1
"""Report written, with error-level findings (or warnings under ``--strict``)."""
NO_REPORT = 2
"""No report: usage error, unreadable file, invalid model."""

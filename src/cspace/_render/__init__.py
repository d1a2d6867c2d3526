"""Renderers of reports: ``text`` and ``markdown`` (JSON is ``Report.to_dict``)."""

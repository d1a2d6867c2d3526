"""Reports, saved and compared.

``report`` is the record, ``savedreport`` reads a saved one back, ``diff`` compares two
and ``summary`` tabulates many.
"""

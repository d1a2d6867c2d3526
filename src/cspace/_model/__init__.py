"""The model: Pinocchio, classification and findings.

``adapter`` is Pinocchio behind one layer (``native`` runs its C++ parser quietly, on a
thread with a stack of its own), ``analysis`` and ``diagnostics`` are the
analysis (through the one joint table, `_joint_table`) and its findings,
``loader`` the front door.
"""

"""The model: Pinocchio, classification and findings.

``adapter`` is Pinocchio behind one layer, ``joint_table`` the one table from a joint
(its Pinocchio joint model and limits) to its kind, factors and coordinates, ``analysis`` and
``diagnostics`` are the analysis and its findings, ``loader`` the front door.
"""

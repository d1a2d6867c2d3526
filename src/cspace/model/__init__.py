"""The model: Pinocchio, classification and findings.

``adapter`` is Pinocchio behind one layer, ``kinds`` the joint table, ``analysis`` and
``diagnostics`` the analysis and its findings, ``loader`` the front door.
"""

"""The model: Pinocchio, classification and findings.

``adapter`` is Pinocchio behind one layer, ``kinds`` maps a joint model to its kind and
space, ``joint_factors`` a joint to its factors and coordinates, ``analysis`` and
``diagnostics`` are the analysis and its findings, ``loader`` the front door.
"""

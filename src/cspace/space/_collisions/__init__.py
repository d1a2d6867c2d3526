"""Self-collision over the configuration space: C-obs from the robot's own links, sampled.

`run.collisions` is ``cspace collisions``: `setup.prepare` reads the robot and its
collision shapes (the engine in ``cspace._model._collision_*``), `tally.tally` checks
seeded uniform samples of its C-space, `classes.report_of` sorts the pairs and makes
the findings, `srdf` reads an SRDF's matrix as MoveIt applies it and writes the one
cspace suggests.
"""

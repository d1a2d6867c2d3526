"""Format readers: a robot file's bytes to a format-free description (no Pinocchio).

``table`` holds every format, one row each; ``detect`` tells an XML file's format. One
sub-package a format (``urdf``, ``xacro``, ``mjcf``, ``sdf``, ``usd``, ``srdf``), each
with its ``reader``; ``shared`` holds what they share (the reader contract, safe XML
input, poses, the structure checks) and ``discovery`` a folder's search.
"""

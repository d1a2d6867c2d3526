"""Confined child processes, for work that cannot be bounded in-process.

``sandbox`` is the runner and its limits; ``seccomp`` and ``landlock`` are the kernel
layers.
"""

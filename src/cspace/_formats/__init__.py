"""Format readers: a robot file's bytes to a format-free description (no Pinocchio).

``urdf``, ``sdf``, ``mjcf`` (with ``mjcf_prescan``, ``mjcf_worker``, ``mjcf_compile``,
``mjcf_equality``), ``xacrofile`` (with ``xacro_sandbox``, ``xacro_worker``) and ``erd``
read; ``xmlio`` reads safely; ``description``, ``kinematic_tree`` and ``structure`` are
what they produce and check.
"""

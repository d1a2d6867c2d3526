"""Collision meshes: STL, OBJ, MuJoCo's MSH and a COLLADA subset, read from bytes.

The readers (`_stl`, `_obj`, `_msh`, `_dae`) parse bytes only: the parent reads each
mesh file through the one way in (`cspace.files.read_input`, in `load.load_meshes`), and
`load.parse_meshes` parses a robot's meshes in one confined child process (`_worker`)
with CPU and memory limits, which answers with the arrays or a one-line error for each
mesh. Every reader
gives float64 vertices ``(n, 3)`` and int32 triangles ``(m, 3)``, scaled by the file's
``(sx, sy, sz)``; NumPy is imported only where arrays are made, never by the parent's
readers of robot files.

The bounds (`_bounds`), each refused with one line naming the mesh:

- `MAX_MESH_BYTES` (32 MiB) a mesh file, `MAX_ROBOT_MESH_BYTES` (128 MiB) all the mesh
  files of a robot;
- `MAX_MESH_VERTICES` (1,000,000) and `MAX_MESH_TRIANGLES` (2,000,000) a mesh,
  `MAX_TOTAL_VERTICES` (4,000,000) and `MAX_TOTAL_TRIANGLES` (8,000,000) a robot;
- `MAX_OBJ_LINES` (4,000,000) lines of an OBJ file;
- `MAX_DAE_NODES` (10,000) ``<node>`` elements of a COLLADA file and `MAX_DAE_DEPTH` (64)
  their nesting; `MAX_DAE_INSTANCES` (10,000) geometries placed; the XML reader's own
  bounds (tags, attributes, no entities, no DTD, text nodes of at most 10 MB) too;
- in the child: `MeshLimits` (CPU seconds, wall-clock seconds, memory).

Refused too: a vertex index out of range, a vertex that is NaN or infinite (after
scaling), a truncated file, a header whose counts do not match the file's size.
"""

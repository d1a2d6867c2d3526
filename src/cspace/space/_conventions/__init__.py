"""The maps between cspace's canonical coordinates and each tool's (`cspace.conventions`).

One module a tool, each ending in a class ``Maps`` (`_maps.Maps`), named by the registry
(`cspace._tools.TOOLS`) and imported when the tool is first used; `_conventions` holds
`Conventions`, which dispatches every map, `_named` values named by joint and
`_joint_blocks` each joint's blocks. They read the space's geometry (`space._geometry`,
`space._checks`); the space's facade reaches them, so they live inside the space.
"""

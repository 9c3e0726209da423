"""Everything that touches bpy: scene extraction, the render engine and its UI."""

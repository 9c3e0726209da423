// The occupancy volumes a lookup or a march reads (gpu/occupancy.py): declared once, so a
// shader that both looks a light grid up and marches its levels shares them.
uniform usampler3D occupancy;
uniform usampler3D coarse;
uniform int voxels_per_cell;

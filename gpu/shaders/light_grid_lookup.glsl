// Irradiance from a light grid (light_grid_gather.comp): the ambient cube of the eight cell
// centres around q = p + n cell/2, each weighted by its trilinear weight if it lies in front
// of the surface, and by whether the surface sees it through the occupancy (no light
// through a wall thinner than a cell, none from the inside of a closed box); a centre on a
// surface is left out. Where q lies in a wall's voxels (p within a voxel of a wall it meets,
// such as a floor at the wall's foot), the march starts instead from q moved a voxel (or
// two: a thin wall's voxels) along each axis toward whoever sees p (`toward`, the camera
// or a reflecting point): out of the wall's voxels on p's own side, which its viewer is
// on; with no such start the grid sees nothing. Where every centre is hidden (the
// surface's own voxels around a convex edge), a second march from the same start passes
// the voxels within EDGE_RADIUS of p (a march passing them every time lets a wall that
// meets the surface at an inner edge let through the cells beyond it; one from inside a
// wall's voxels crosses a thin wall). The fourth component is 1
// where any centre counts, else 0: such a grid abstains (light_grid_levels.glsl) instead of
// answering black. With PAIRED, each centre gives the luminances (`luminance_weights`,
// declared before) of two grids' light instead: the light grid's in r and
// `unshadowed_grid`'s in g, through the same marches. With ROOMS only the centres in the
// room `lookup_room` count (`cell_rooms`: 1 + each cell's room, light_grid_rooms.comp),
// which its caller sets to the surface side's room.
#include "occupancy.glsl"
uniform sampler3D light_grid[GRIDS];
#ifdef ROOMS
uniform usampler3D cell_rooms;
int lookup_room = 0;
#endif
#ifdef PAIRED
uniform sampler3D unshadowed_grid[GRIDS];
#endif
#include "occupancy_volumes.glsl"
const float EDGE_RADIUS = 1.5;  // voxels around the surface point a second march passes

// The irradiance of the ambient cube of `volume`'s cell c on a surface whose normal has
// the squares n2 and faces the +axis (0) or -axis (1) block of each axis (`side`).
vec3 ambient_cube(sampler3D volume, ivec3 c, vec3 n2, ivec3 side) {
    return n2.x * texelFetch(volume, ivec3(c.xy, c.z + side.x * grid_size), 0).rgb
         + n2.y * texelFetch(volume, ivec3(c.xy, c.z + (2 + side.y) * grid_size), 0).rgb
         + n2.z * texelFetch(volume, ivec3(c.xy, c.z + (4 + side.z) * grid_size), 0).rgb;
}

// Whether the voxel at x (voxel units of `grid`) holds a surface; not outside the grid.
bool voxel_occupied(int grid, vec3 x) {
    int voxels = textureSize(coarse, 0).x * voxels_per_cell;
    ivec3 v = ivec3(floor(x));
    return all(greaterThanEqual(v, ivec3(0))) && all(lessThan(v, ivec3(voxels)))
        && texelFetch(occupancy, v + ivec3(0, 0, grid * voxels), 0).r != 0u;
}

// The weighted sum of the visible centres' irradiance and the sum of their weights, the
// march starting `shift` voxels from q and passing the voxels within `radius` of p.
vec4 visible_centres(int grid, vec3 p, vec3 n, vec3 shift, float radius) {
    float cell = cell_sizes[grid];
    vec3 origin = grid_origins[grid];
    vec3 q = p + 0.5 * cell * n;
    vec3 g = (q - origin) / cell - 0.5;
    ivec3 base = ivec3(floor(g));
    vec3 f = g - vec3(base);
    float voxel = cell / float(voxels_per_cell);
    vec3 start_voxels = (q - origin) / voxel + shift;
    vec3 surface_voxels = (p - origin) / voxel;
    vec3 n2 = n * n;
    ivec3 side = ivec3(n.x < 0.0 ? 1 : 0, n.y < 0.0 ? 1 : 0, n.z < 0.0 ? 1 : 0);  // +axis block or -axis
    vec4 sum = vec4(0.0);
    for (int corner = 0; corner < 8; ++corner) {
        ivec3 step = ivec3(corner & 1, (corner >> 1) & 1, corner >> 2);
        ivec3 c = clamp(base + step, ivec3(0), ivec3(grid_size - 1));
        vec3 w3 = mix(1.0 - f, f, vec3(step));
        vec3 centre_voxels = (vec3(c) + 0.5) * float(voxels_per_cell);
        vec3 to = (vec3(c) + 0.5) * cell + origin - p;
        float weight = dot(to, n) > 0.0 ? w3.x * w3.y * w3.z : 0.0;
#ifdef ROOMS
        if (texelFetch(cell_rooms, c + ivec3(0, 0, grid * grid_size), 0).r != uint(1 + lookup_room)) continue;
#endif
        if (weight <= 0.0 || segment_blocked(occupancy, coarse, voxels_per_cell, grid, start_voxels, centre_voxels, surface_voxels,
                                                radius, false))
            continue;
#ifdef PAIRED
        vec3 e = vec3(dot(ambient_cube(light_grid[grid], c, n2, side), luminance_weights),
                      dot(ambient_cube(unshadowed_grid[grid], c, n2, side), luminance_weights), 0.0);
#else
        vec3 e = ambient_cube(light_grid[grid], c, n2, side);
#endif
        sum += weight * vec4(e, 1.0);
    }
    return sum;
}

// A march skips the voxel it starts in: from a start in a wall's voxels it would reach
// either side of the wall, so such a start sees nothing.
vec4 grid_irradiance(int grid, vec3 p, vec3 n, vec3 toward) {
    vec3 q_voxels = (p + 0.5 * cell_sizes[grid] * n - grid_origins[grid]) * float(voxels_per_cell) / cell_sizes[grid];
    vec3 across = toward - dot(toward, n) * n;  // toward the viewer along the surface
    vec3 shift = sign(across) * step(0.1 * length(across), abs(across));
    vec4 sum = vec4(0.0);
    vec3 start = vec3(0.0);
    bool free_start = !voxel_occupied(grid, q_voxels);
    for (int k = 1; k <= 2 && !free_start && any(notEqual(shift, vec3(0.0))); ++k) {
        start = float(k) * shift;
        free_start = !voxel_occupied(grid, q_voxels + start);
    }
    if (free_start) {
        sum = visible_centres(grid, p, n, start, 0.0);
        if (sum.a <= 1e-8) sum = visible_centres(grid, p, n, start, EDGE_RADIUS);
    }
    return sum.a > 1e-8 ? vec4(sum.rgb / sum.a, 1.0) : vec4(0.0);
}

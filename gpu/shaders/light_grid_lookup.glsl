// Irradiance from a light grid (light_grid_gather.comp): the ambient cube of the eight cell
// centres around p + n cell/2, each weighted by its trilinear weight if it lies in front of
// the surface, and by whether the surface sees it through the occupancy (no light
// through a wall thinner than a cell, none from the inside of a closed box); a centre on a
// surface is left out. A march that counts no voxel near p as passable keeps a wall that
// meets the surface at an inner edge from letting through the cells beyond it; where it
// finds every centre hidden (the surface's own voxels around a convex edge), the voxels
// within EDGE_RADIUS of p are passed. The fourth component is 1 where any centre
// counts, else 0: such a grid abstains (light_grid_levels.glsl) instead of answering black.
#include "occupancy.glsl"
uniform sampler3D light_grid[GRIDS];
#include "occupancy_volumes.glsl"
const float EDGE_RADIUS = 1.5;  // voxels around the surface point a second march passes

// The weighted sum of the visible centres' irradiance and the sum of their weights, the
// march passing the voxels within `radius` of p.
vec4 visible_centres(int grid, vec3 p, vec3 n, float radius) {
    float cell = cell_sizes[grid];
    vec3 origin = grid_origins[grid];
    vec3 q = p + 0.5 * cell * n;
    vec3 g = (q - origin) / cell - 0.5;
    ivec3 base = ivec3(floor(g));
    vec3 f = g - vec3(base);
    float voxel = cell / float(voxels_per_cell);
    vec3 q_voxels = (q - origin) / voxel;
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
        if (weight <= 0.0 || segment_blocked(occupancy, coarse, voxels_per_cell, grid, q_voxels, centre_voxels, surface_voxels,
                                                radius, false))
            continue;
        vec3 e = n2.x * texelFetch(light_grid[grid], ivec3(c.xy, c.z + side.x * grid_size), 0).rgb
               + n2.y * texelFetch(light_grid[grid], ivec3(c.xy, c.z + (2 + side.y) * grid_size), 0).rgb
               + n2.z * texelFetch(light_grid[grid], ivec3(c.xy, c.z + (4 + side.z) * grid_size), 0).rgb;
        sum += weight * vec4(e, 1.0);
    }
    return sum;
}

vec4 grid_irradiance(int grid, vec3 p, vec3 n) {
    vec4 sum = visible_centres(grid, p, n, 0.0);
    if (sum.a <= 1e-8) sum = visible_centres(grid, p, n, EDGE_RADIUS);
    return sum.a > 1e-8 ? vec4(sum.rgb / sum.a, 1.0) : vec4(0.0);
}

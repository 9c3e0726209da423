// The light of LEVELS nested grid levels (gpu/grids.py) at a surface, each level PHASES
// grids offset by a fraction of a cell whose answers are averaged: a pixel takes the
// finest level that holds it, blended into the next over the last cells of its box. A
// grid that does not answer (grid_irradiance's fourth component 0) leaves its phase out
// of the average, and a level of none its share to the next.
// Needs grid_origins, cell_sizes, grid_size and a lookup's grid_irradiance(grid, p, n, toward),
// `toward` the unit direction from p to whoever sees it.

// How much a level answers at q: all of it from two cells inside its box, none within one.
float level_share(int grid, vec3 q) {
    vec3 g = (q - grid_origins[grid]) / cell_sizes[grid];
    vec3 inside = min(g, float(grid_size) - g);
    return clamp(min(inside.x, min(inside.y, inside.z)) - 1.0, 0.0, 1.0);
}

vec3 levels_irradiance(vec3 p, vec3 n, vec3 toward) {
    vec3 irradiance = vec3(0.0);
    float remaining = 1.0;
    for (int level = 0; level < LEVELS && remaining > 0.0; ++level) {
        float share = level == LEVELS - 1 ? 1.0 : level_share(level * PHASES, p);
        if (share <= 0.0) continue;
        vec4 level_light = vec4(0.0);
        for (int phase = 0; phase < PHASES; ++phase) level_light += grid_irradiance(level * PHASES + phase, p, n, toward);
        if (level_light.a <= 0.0) continue;
        irradiance += remaining * share * level_light.rgb / level_light.a;
        remaining *= 1.0 - share;
    }
    return irradiance;
}

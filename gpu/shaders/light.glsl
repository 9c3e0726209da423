// One light's emission with Cycles' conventions (see gpu/scene.py Light).
#define LIGHT_POINT 0
#define LIGHT_SPOT 1
#define LIGHT_AREA 2
#define LIGHT_SUN 3

uniform int light_kind;
uniform vec3 light_position;   // for a sun: a point on the plane its shadow map starts at
uniform vec3 light_direction;  // the light's -Z axis
uniform vec3 light_peak;       // W/sr at the peak; W/m^2 for a sun
uniform float spot_cos_half;
uniform float spot_smooth;     // 1 / ((1 - cos_half) * blend), large when blend is 0

// Radiant intensity toward unit direction w (light to point); irradiance for a sun.
vec3 light_intensity(vec3 w) {
    if (light_kind == LIGHT_SPOT) {
        float x = clamp((dot(w, light_direction) - spot_cos_half) * spot_smooth, 0.0, 1.0);
        return light_peak * (x * x * (3.0 - 2.0 * x));
    }
    if (light_kind == LIGHT_AREA) {
        return light_peak * max(dot(w, light_direction), 0.0);
    }
    return light_peak;
}

// Irradiance the light gives a surface at distance `dist` along `w` (light_ray's) whose
// normal makes `cos_theta` with -w (unshadowed).
vec3 light_irradiance(vec3 w, float dist, float cos_theta) {
    return light_kind == LIGHT_SUN ? light_peak * cos_theta
                                   : light_intensity(w) * cos_theta / max(dist * dist, 1e-30);
}

// Direction from the light toward p, and the distance its shadow map stores.
void light_ray(vec3 p, out vec3 w, out float dist) {
    if (light_kind == LIGHT_SUN) {
        w = light_direction;
        dist = dot(p - light_position, light_direction);
    } else {
        vec3 d = p - light_position;
        dist = length(d);
        w = d / max(dist, 1e-30);
    }
}

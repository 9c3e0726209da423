// A point emitter (gpu/light_grid.py): a VPL, or a cluster of them. position.w > 0: valid;
// normal.xyz: the unit normal of a cosine emitter, the axis of a glossy one's lobe, zero
// for one that emits alike in every direction; normal.w: the area it stands for; flux.rgb:
// its flux (W); flux.w: below 0 a glossy emitter's lobe width, negated, else the share
// whose bound is held (held_share).
struct Emitter { vec4 position; vec4 normal; vec4 flux; };

// A glossy emitter sends a glossy layer's reflection of its light (gpu/vpl.py) about its
// mirror direction m as a GGX surface of alpha a = -flux.w reflects light arriving along
// its normal: toward w at angle theta from m, D_a(theta / 2) / 4 of its flux per sr, the
// half-vector's GGX density over the reflection's Jacobian (4 cos(theta / 2)) times
// cos(theta / 2). It sums to the flux over the sphere; toward the light it keeps GGX's
// tail.
bool glossy_lobe(Emitter e) { return e.flux.w < 0.0; }

// An emitter's radiant intensity toward unit direction w over its flux.
float emitter_intensity(Emitter e, vec3 w) {
    if (glossy_lobe(e)) {
        float a2 = e.flux.w * e.flux.w;
        float half_cos2 = 0.5 + 0.5 * dot(e.normal.xyz, w);  // cos^2(theta / 2)
        float denominator = half_cos2 * (a2 - 1.0) + 1.0;
        return 0.25 * a2 / (PI * denominator * denominator);
    }
    bool cosine = dot(e.normal.xyz, e.normal.xyz) > 0.5;
    return cosine ? max(0.0, dot(e.normal.xyz, w)) / PI : 0.25 / PI;
}

// Whether the emitter lights as a square of its area facing its normal (square_faces).
bool square_emitter(Emitter e) { return dot(e.normal.xyz, e.normal.xyz) > 0.5 && !glossy_lobe(e); }

// Irradiance an emitter gives a surface at distance vector d from it, facing it: its
// radiant intensity toward d over r^2, bounded next to it by the area A it stands for,
// in one of two ways (docs/method.md, "The 1/r² bound"). Its share 1 - h grows r^2 by
// `grown` A/pi, as a disk of area A gives on its axis (pi L R^2 / (r^2 + R^2)): the pixel
// gather's converging frames shrink that bound set by set, so its bias tends to zero. Its
// share h holds r^2 at least at `held` A/pi: within the disk's radius R the exitance the
// disk gives at its centre, beyond R exact, which takes little light where the bound never
// shrinks (growing it took a fifth of the light at 2R and a tenth at 3R).
uniform float singularity_bound;
vec3 bounded_emitter_light(Emitter e, vec3 d, float grown, float held, float h) {
    float r2 = dot(d, d);
    vec3 w = d * inversesqrt(max(r2, 1e-30));
    float intensity = emitter_intensity(e, w);
    float area = e.normal.w / PI;
    return e.flux.rgb * intensity * ((1.0 - h) / (r2 + grown * area + 1e-30) + h / (max(r2, held * area) + 1e-30));
}

// The share of an emitter's flux whose bound is held (flux.w): 1 for a point the emitters'
// bounce or a later bounce lit (emitter_bounce.comp), a light grid cluster's flux-weighted
// share of such points (emitter_cluster.comp), 0 for the lights' VPLs, glossy emitters and the rest.
float held_share(Emitter e) { return clamp(e.flux.w, 0.0, 1.0); }

// With `singularity_bound` grown for all of its flux (settings.py singularity_bound).
vec3 emitter_light(Emitter e, vec3 d) { return bounded_emitter_light(e, d, singularity_bound, 0.0, 0.0); }

// With its held share held at `held`, the rest grown by `grown`.
vec3 shared_emitter_light(Emitter e, vec3 d, float grown, float held) {
    return bounded_emitter_light(e, d, grown, held, held_share(e));
}

// Lambert's edge integral of the polygon edge from unit direction a to b over 2 pi: the angle
// between them times their normalised cross product, with Heitz et al.'s fit of
// theta / (2 pi sin(theta)).
vec3 edge_integral(vec3 a, vec3 b) {
    float x = dot(a, b);
    float y = abs(x);
    float v = (0.8543985 + (0.4965155 + 0.0145206 * y) * y) / (3.4175940 + (4.1616724 + y) * y);
    float theta_over_sine = x > 0.0 ? v : 0.5 * inversesqrt(max(1.0 - x * x, 1e-7)) - v;
    return cross(a, b) * theta_over_sine;
}

// The irradiance at p of a cosine emitter spread evenly over a square of the area it stands
// for, facing its normal, on surfaces facing +x, +y, +z (`plus`) and -x, -y, -z (`minus`),
// times `colour` (its radiance, flux / (pi A)): per face the projected solid angle of the
// part of the square before it (Lambert's formula on the square cut by the face's plane);
// beyond SQUARE_SIDES sides, or of no area, a point's flux / pi times cos / r^2.
// Squares tiling a lit plane give a point near it the plane's light wherever it falls,
// where points with a bounded 1/r^2 swing from far too little to far too much
// (docs/method.md, "Light grid").
const float SQUARE_SIDES = 2.0;
void square_faces(Emitter e, vec3 p, out vec3 colour, out vec3 plus, out vec3 minus) {
    vec3 d = p - e.position.xyz;
    vec3 n = e.normal.xyz;
    float r2 = dot(d, d), area = max(e.normal.w, 0.0);
    float facing = dot(d, n);
    plus = minus = vec3(0.0);
    colour = vec3(0.0);
    if (facing <= 0.0 || r2 <= 0.0) return;
    if (r2 > SQUARE_SIDES * SQUARE_SIDES * area) {  // a point: its intensity flux cos / pi over r^2
        colour = e.flux.rgb / PI;
        vec3 toward = -d * (facing / max(r2 * r2, 1e-30));
        plus = max(toward, 0.0);
        minus = max(-toward, 0.0);
        return;
    }
    colour = e.flux.rgb / (PI * area);
    float s = n.z >= 0.0 ? 1.0 : -1.0;  // an orthonormal basis around n (Duff et al. 2017)
    float a = -1.0 / (s + n.z), b = n.x * n.y * a;
    vec3 t = 0.5 * sqrt(area) * vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
    vec3 u = 0.5 * sqrt(area) * vec3(b, s + n.y * n.y * a, -n.y);
    vec3 q[4] = vec3[4](-d - t - u, -d + t - u, -d + t + u, -d - t + u);  // the corners, seen from p
    vec3 corner[4], edge[4];
    for (int i = 0; i < 4; ++i) corner[i] = normalize(q[i]);
    for (int i = 0; i < 4; ++i) edge[i] = edge_integral(corner[i], corner[(i + 1) & 3]);
    float winding = dot(edge[0] + edge[1] + edge[2] + edge[3], n) < 0.0 ? PI : -PI;  // toward the square
    vec3 whole = winding * (edge[0] + edge[1] + edge[2] + edge[3]);
    for (int axis = 0; axis < 3; ++axis) {
        float low = min(min(q[0][axis], q[1][axis]), min(q[2][axis], q[3][axis]));
        float high = max(max(q[0][axis], q[1][axis]), max(q[2][axis], q[3][axis]));
        float before = high <= 0.0 ? 0.0 : whole[axis];  // the light from the part on the axis' + side
        if (low < 0.0 && high > 0.0) {  // the square's edges on that side, and the cut between where it leaves and comes back
            vec3 part = vec3(0.0), leaves = vec3(0.0), returns = vec3(0.0);
            for (int i = 0; i < 4; ++i) {
                vec3 from = q[i], to = q[(i + 1) & 3];
                bool from_before = from[axis] >= 0.0, to_before = to[axis] >= 0.0;
                if (from_before && to_before) {
                    part += edge[i];
                } else if (from_before || to_before) {
                    vec3 cut = normalize(mix(from, to, from[axis] / (from[axis] - to[axis])));
                    if (from_before) {
                        leaves = cut;
                        part += edge_integral(corner[i], cut);
                    } else {
                        returns = cut;
                        part += edge_integral(cut, corner[(i + 1) & 3]);
                    }
                }
            }
            before = winding * (part + edge_integral(leaves, returns))[axis];
        }
        plus[axis] = max(before, 0.0);
        minus[axis] = max(before - whole[axis], 0.0);
    }
}

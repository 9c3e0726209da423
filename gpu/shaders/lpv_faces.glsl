// The faces a propagation step sends a cell's light through (METHOD §7): toward each of
// the six neighbours, straight through the far face and through four side faces, each
// face's flux estimated as the intensity toward its centre times its solid angle.
const float FAR_FACE_SOLID_ANGLE = 0.4006696846;
const float SIDE_FACE_SOLID_ANGLE = 0.4234313544;
const ivec3 DIRECTIONS[6] = ivec3[6](ivec3(1, 0, 0), ivec3(-1, 0, 0), ivec3(0, 1, 0),
                                     ivec3(0, -1, 0), ivec3(0, 0, 1), ivec3(0, 0, -1));

// Direction toward the centre of the side face s of the neighbour along d.
vec3 side_face_direction(vec3 d, vec3 s) {
    return (2.0 * d + s) / sqrt(5.0);
}

// The flux the faces' estimates send out of a cell of SH intensity `sh`, in all.
float outgoing_flux(vec4 sh) {
    float flux = 0.0;
    for (int i = 0; i < 6; ++i) {
        vec3 d = vec3(DIRECTIONS[i]);
        flux += max(0.0, dot(sh, sh_basis(d))) * FAR_FACE_SOLID_ANGLE;
        for (int j = 0; j < 6; ++j) {
            vec3 s = vec3(DIRECTIONS[j]);
            if (dot(s, d) != 0.0) continue;
            flux += max(0.0, dot(sh, sh_basis(side_face_direction(d, s)))) * SIDE_FACE_SOLID_ANGLE;
        }
    }
    return flux;
}

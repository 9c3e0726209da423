// A surface's diffuse colour (mesh_buffer.py, surface_images.py): the vertex albedo times
// the image layer at the surface coordinate (u, v, layer) where it has an image.
uniform sampler2DArray surface_images;

vec3 surface_colour(vec3 albedo, vec3 coord) {
    if (coord.z < -0.5) return albedo;
    return albedo * texture(surface_images, vec3(coord.xy, floor(coord.z + 0.5))).rgb;
}

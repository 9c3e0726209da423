// The scene's vertex (gpu/mesh_buffer.py VERTEX_LAYOUT), as the compute passes read it
// from the vertex buffer: position, normal, albedo and alpha, surface coordinate (u, v,
// image layer, alpha image layer), transmission (tint rgb, share), specular (F0 rgb, roughness), metallic.
const int VERTEX_FLOATS = 23;
const int VERTEX_NORMAL = 3;
const int VERTEX_ALBEDO = 6;
const int VERTEX_ALPHA = 9;         // the alpha float
const int VERTEX_SURFACE = 10;      // u, v, image layer, alpha image layer
const int VERTEX_ALPHA_LAYER = 13;  // the alpha image's layer (-1: none)
const int VERTEX_TINT = 14;         // the transmission's tint rgb, then its share
const int VERTEX_TRANSMISSION = 17; // the transmitted share
const int VERTEX_SPECULAR = 18;     // F0 rgb, roughness
const int VERTEX_METALLIC = 22;

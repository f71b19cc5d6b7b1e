// What the renderer draws: plain data, no physics types, no GL types. The glue
// in scenes/ turns a world into a DrawList; every consumer (golden checks,
// videos, the window, report plots) hands one to render::Renderer.
//
// Units: positions and sizes in metres in the world (Y up), overlays in pixels
// with the origin at the top-left of the image. Colours are sRGB, 0..1.
//
// Contents
//   Colour and look ........ Color, Look (solid or ghost)
//   3D items ............... Sphere, Capsule, Cylinder, Box, Cone, Arrow, Mesh,
//                            Ribbon, Plane, Ground
//   View ................... Camera, Light, RenderSettings
//   Overlays ............... Text, Plot
//   DrawList
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace render {

using Vec2 = Eigen::Vector2f;
using Vec3 = Eigen::Vector3f;

// sRGB colour with straight (not premultiplied) alpha.
struct Color {
    float r = 0.8f, g = 0.8f, b = 0.8f, a = 1.0f;
};

// How an item is drawn. A ghost is the same item semi-transparent and lighter
// (the analytic solution beside the simulated one); it casts no shadow.
struct Look {
    Color color;
    bool ghost = false;
};

// --- 3D items -----------------------------------------------------------------

struct Sphere {
    Vec3 center = Vec3::Zero();  // m
    float radius = 0.1f;         // m
    Look look;
};

// A cylinder with hemispherical caps from a to b.
struct Capsule {
    Vec3 a = Vec3::Zero(), b = Vec3::UnitY();  // m, centres of the two caps
    float radius = 0.05f;                      // m
    Look look;
};

// A closed cylinder from a to b: springs, links, rods.
struct Cylinder {
    Vec3 a = Vec3::Zero(), b = Vec3::UnitY();  // m, centres of the two end discs
    float radius = 0.02f;                      // m
    Look look;
};

struct Box {
    Vec3 center = Vec3::Zero();                                    // m
    Vec3 half_extents = Vec3::Constant(0.5f);                      // m, along the box's own axes
    Eigen::Quaternionf rotation = Eigen::Quaternionf::Identity();  // box axes to world
    Look look;
};

// A cone from its base centre to its apex.
struct Cone {
    Vec3 base = Vec3::Zero(), apex = Vec3::UnitY();  // m
    float radius = 0.05f;                            // m, base radius
    Look look;
};

// A vector drawn from `origin` to `origin + vector`: a shaft and a head.
// Radii of 0 mean "choose from the length" (shaft 3%, head 8% of the length,
// head at most 30% of it).
struct Arrow {
    Vec3 origin = Vec3::Zero();   // m
    Vec3 vector = Vec3::UnitY();  // m (a velocity or force already scaled to metres)
    float shaft_radius = 0.0f;    // m
    float head_radius = 0.0f;     // m
    Look look;
};

// Triangles with per-vertex normals and colours: cloth, soft bodies, static
// collider meshes. Both faces are lit (cloth is seen from both sides).
struct Mesh {
    std::vector<Vec3> positions;         // m
    std::vector<Vec3> normals;           // unit; empty: computed from the triangles
    std::vector<Color> colors;           // per vertex; empty: `look.color` everywhere
    std::vector<std::uint32_t> indices;  // three per triangle
    Look look;
};

// A trail: a flat band through the points that turns to face the camera,
// fading from transparent at the first point to `look.color` at the last.
struct Ribbon {
    std::vector<Vec3> points;  // m, oldest first
    float width = 0.02f;       // m
    Look look;
};

// A finite rectangle: a static plane collider, a wall, a ramp.
struct Plane {
    Vec3 center = Vec3::Zero();   // m
    Vec3 normal = Vec3::UnitY();  // unit, the lit side
    Vec2 size{4.0f, 4.0f};        // m, extent along the plane's two in-plane axes
    Look look;
};

// The ground: a large horizontal plane at height y with a grid, which receives
// the shadows. Lines every `grid_spacing` metres, a stronger line every
// `major_every` lines.
struct Ground {
    bool enabled = true;
    float height = 0.0f;        // m
    float extent = 50.0f;       // m, half-size of the square
    float grid_spacing = 1.0f;  // m
    int major_every = 5;
    Color color{0.82f, 0.82f, 0.80f, 1.0f};
    Color line_color{0.55f, 0.55f, 0.55f, 1.0f};
};

// --- View ---------------------------------------------------------------------

struct Camera {
    enum class Projection { perspective, orthographic };
    Projection projection = Projection::perspective;
    Vec3 eye{4.0f, 3.0f, 6.0f};  // m
    Vec3 target = Vec3::Zero();  // m, point at the centre of the image
    Vec3 up = Vec3::UnitY();
    float fov_y_deg = 40.0f;    // degrees, vertical field of view (perspective)
    float ortho_height = 4.0f;  // m, visible height (orthographic)
    float near_plane = 0.05f;   // m
    float far_plane = 200.0f;   // m
};

// One directional light plus ambient (Blinn-Phong), with a shadow map.
struct Light {
    Vec3 direction{-0.4f, -1.0f, -0.3f};  // direction the light travels (need not be unit)
    float intensity = 0.85f;              // diffuse scale, 0..1
    float ambient = 0.32f;                // ambient scale, 0..1
    float specular = 0.25f;               // Blinn-Phong specular scale
    float shininess = 48.0f;              // Blinn-Phong exponent
    bool shadows = true;
};

// --- Overlays (screen space, pixels, origin top-left) ---------------------------

struct Text {
    std::string text;     // UTF-8, '\n' for new lines
    Vec2 position{8, 8};  // px, top-left corner of the text box
    float size = 16.0f;   // px, text height
    Color color{0.1f, 0.1f, 0.1f, 1.0f};
    bool backdrop = false;  // a translucent panel behind the text, for legibility over a scene
};

// A 2D plot panel: line series with axes, ticks, labels and a legend.
struct Plot {
    struct Series {
        std::string name;          // legend entry; empty: not in the legend
        std::vector<Vec2> points;  // data units
        Color color{0.1f, 0.3f, 0.8f, 1.0f};
        float width = 2.0f;  // px
    };
    Vec2 position{8, 8};  // px, top-left of the panel
    Vec2 size{320, 200};  // px
    std::string title;
    std::string x_label, y_label;
    std::vector<Series> series;
    std::optional<Vec2> x_range;  // data units; empty: fitted to the data
    std::optional<Vec2> y_range;
    float text_size = 13.0f;  // px
    Color background{1.0f, 1.0f, 1.0f, 0.85f};
    Color foreground{0.15f, 0.15f, 0.15f, 1.0f};  // axes, ticks, labels
};

// --- The list -------------------------------------------------------------------

struct DrawList {
    Camera camera;
    Light light;
    Color background{0.93f, 0.95f, 0.98f, 1.0f};  // sky
    Ground ground;

    std::vector<Sphere> spheres;
    std::vector<Capsule> capsules;
    std::vector<Cylinder> cylinders;
    std::vector<Box> boxes;
    std::vector<Cone> cones;
    std::vector<Arrow> arrows;
    std::vector<Mesh> meshes;
    std::vector<Ribbon> ribbons;
    std::vector<Plane> planes;

    std::vector<Text> texts;
    std::vector<Plot> plots;
};

// How a frame is made, separate from what is in it.
struct RenderSettings {
    int width = 640;             // px
    int height = 480;            // px
    int msaa_samples = 0;        // 0 or 1: off (goldens); 4 for videos and the window
    int shadow_map_size = 1024;  // texels per side (2048 costs 6 ms more per frame on llvmpipe)
    // The scene moved by this much on the image, px (x right, y down), by
    // the projection alone: overlays stay. Frames jittered over a grid of
    // sub-pixel offsets and averaged are a supersampled reference (the
    // anti-aliasing test's); 0 otherwise.
    float jitter_x = 0.0f, jitter_y = 0.0f;
    // The scene is drawn at this fraction of width x height per side (the
    // render targets are that size, rounded), 0.25 .. 1, and blit_to_window
    // scales the frame up to width x height, then draws the overlays over it
    // at that size: text and plots stay sharp whatever the scale. Below 1: a
    // viewer's dynamic resolution (fewer pixels to shade while a heavy scene
    // runs); read_back then returns the smaller image, the scene without its
    // overlays.
    float scale = 1.0f;
    bool operator==(const RenderSettings&) const = default;
};

// The MSAA sample counts the renderer takes: 0 or 1 (off), 2, 4 or 8. The one
// check, for the renderer and for the commands that take --msaa; a driver may
// still allow fewer (Renderer::draw says so).
constexpr bool supported_msaa_samples(int samples) {
    return samples == 0 || samples == 1 || samples == 2 || samples == 4 || samples == 8;
}

}  // namespace render

/* depthcull: the C API (C99), for engines in C, C#, Rust, Zig, Odin, Go
 * or Lua. It covers per-image analysis (paper 2.1, 2.2), scene
 * reconstruction into meshes (paper 2.3) with dynamic elements, and the
 * mesh files (docs/mesh-format.md).
 *
 * Conventions
 * - Every function that can fail returns a dc_status; DC_OK is 0. On
 *   failure, dc_last_error() returns a one-line message saying what went
 *   wrong (for files: the file and the place in it). No C++ exception ever
 *   crosses this API.
 * - Objects are opaque handles made by a *_create / *_read / dc_analyze_image
 *   / dc_reconstruct call and released by the matching *_destroy, which
 *   accepts NULL. Out-parameters are written only on success.
 * - Pointers a getter returns (polygon points, vertex and index arrays,
 *   strings) point into the handle: valid until the handle is destroyed or
 *   passed as the output of another call; never free them.
 * - Memory the library hands over (dc_meshes_write_memory) is released with
 *   dc_free.
 * - Input arrays are copied; the caller keeps ownership and may free them
 *   once the call returns.
 * - Threads: calls on different handles may run concurrently; a handle may
 *   be read (const functions) from many threads at once but not changed
 *   while read. dc_last_error is per thread.
 * - The renderer (dc_renderer_*) makes GL calls: its calls, destroy
 *   included, need the host's GL context current on the calling thread.
 * - Coordinates: texel space of an image has its origin at the top-left,
 *   y down; texel (i, j) covers [i, i+1] x [j, j+1]. Screen space likewise,
 *   in pixels. */
#ifndef DEPTHCULL_H
#define DEPTHCULL_H

#include <stddef.h>
#include <stdint.h>

#if defined(_WIN32) && defined(DEPTHCULL_C_BUILD)
#define DC_API __declspec(dllexport)
#elif defined(__GNUC__)
#define DC_API __attribute__((visibility("default")))
#else
#define DC_API
#endif

#ifdef __cplusplus
extern "C" {
#endif

#define DC_VERSION_MAJOR 0
#define DC_VERSION_MINOR 2

typedef enum dc_status {
    DC_OK = 0,
    DC_ERROR_INVALID_ARGUMENT = 1,      /* a NULL handle, an out-of-range value, a rect outside its image */
    DC_ERROR_INVALID_SCENE = 2,         /* reconstruction refused the scene (see dc_last_error) */
    DC_ERROR_TOO_MANY_DEPTH_LEVELS = 3, /* more levels than a 24-bit depth buffer resolves, or dynamic
                                           elements beyond the reserved levels */
    DC_ERROR_IO = 4,                    /* a file could not be read or written, or is not a valid meshes file */
    DC_ERROR_OUT_OF_MEMORY = 5,
    DC_ERROR_INTERNAL = 6,              /* a bug: please report dc_last_error() */
    DC_ERROR_GL = 7,                    /* the runtime renderer: no usable GL 3.3 / ES 3.0, a shader that did
                                           not build, or a GL error */
    DC_ERROR_UNSUPPORTED = 8            /* this build of the library lacks the feature (the runtime renderer) */
} dc_status;

/* The message of the last failed call on this thread ("" before any). */
DC_API const char* dc_last_error(void);
/* "ok", "invalid argument", ...; never NULL. */
DC_API const char* dc_status_string(dc_status status);

typedef struct dc_rect {
    int x, y, w, h; /* [x, x+w) x [y, y+h) */
} dc_rect;

typedef struct dc_point {
    double x, y;
} dc_point;

/* ---- Per-image analysis (paper 2.1, 2.2) */

typedef enum dc_filter { DC_FILTER_NEAREST = 0, DC_FILTER_LINEAR = 1 } dc_filter;
typedef enum dc_opaque_method { DC_OPAQUE_PAPER = 0, DC_OPAQUE_FAST = 1, DC_OPAQUE_GROW = 2 } dc_opaque_method;

typedef struct dc_analyze_options {
    int max_boundary_vertices;       /* per boundary polygon; 10 (values below 4 act as 4) */
    int filter;                      /* dc_filter the renderer samples with; DC_FILTER_NEAREST */
    int split_parts;                 /* 1: one polygon per disjoint part of the image; 1 */
    int opaque_method;               /* dc_opaque_method; DC_OPAQUE_FAST */
    int max_opaque_polygons;         /* 4; 0 finds none */
    double min_opaque_coverage;      /* stop once this fraction of opaque texels is covered; 0.75 */
    int min_opaque_area;             /* texels a new opaque polygon must add; 64 */
} dc_analyze_options;

/* Fills `options` with the defaults above. */
DC_API void dc_analyze_options_default(dc_analyze_options* options);

/* The analyzer's figures. Best cases: boundary_area == nontransparent_texels,
 * opaque_coverage == 1. */
typedef struct dc_image_stats {
    int64_t nontransparent_texels;
    int64_t opaque_texels;
    double boundary_area;          /* summed area of the boundary polygons */
    int boundary_vertices;
    double opaque_area;            /* summed area of the opaque polygons */
    int64_t opaque_covered_texels; /* opaque texels inside opaque polygons */
    double opaque_coverage;        /* covered / opaque texels; 0 when none */
} dc_image_stats;

typedef struct dc_analysis dc_analysis;

/* Boundary polygons (containing every non-transparent texel of `rect`) and
 * opaque polygons (touching only opaque texels, alpha 255) of `rect` in an
 * RGBA8 image (non-premultiplied, rows `stride` bytes apart, stride >=
 * 4 * width). `options` NULL: the defaults. The pixels are not kept. */
DC_API dc_status dc_analyze_image(const uint8_t* rgba, int width, int height, ptrdiff_t stride, dc_rect rect,
                                  const dc_analyze_options* options, dc_analysis** out);
DC_API void dc_analysis_destroy(dc_analysis* analysis);

DC_API dc_rect dc_analysis_rect(const dc_analysis* analysis);
DC_API size_t dc_analysis_boundary_count(const dc_analysis* analysis);
DC_API size_t dc_analysis_opaque_count(const dc_analysis* analysis);
/* Polygon i: `*count` points in texel coordinates of the whole image,
 * clockwise with y down. NULL (and *count = 0) when i is out of range. */
DC_API const dc_point* dc_analysis_boundary(const dc_analysis* analysis, size_t i, size_t* count);
DC_API const dc_point* dc_analysis_opaque(const dc_analysis* analysis, size_t i, size_t* count);
DC_API dc_status dc_analysis_stats(const dc_analysis* analysis, dc_image_stats* out);

/* ---- Scenes (paper 2): images placed as elements, in painter's order */

typedef struct dc_viewport {
    double x, y;       /* world [x, x+width) x [y, y+height) is the framebuffer, y down */
    int width, height;
} dc_viewport;

/* How an element combines with what is behind it; s = texel * colour, a its
 * alpha (the GL blend factors: docs/engine-integration.md). */
typedef enum dc_blend {
    DC_BLEND_ALPHA = 0,    /* s*a + dst*(1-a) */
    DC_BLEND_ADD = 1,      /* s*a + dst */
    DC_BLEND_MULTIPLY = 2, /* dst*(s*a + 1-a): s*dst where the texel is opaque, dst where transparent */
    DC_BLEND_OPAQUE = 3    /* s, texel alpha ignored */
} dc_blend;

typedef struct dc_element {
    uint32_t image;       /* index returned by dc_scene_add_image */
    dc_rect rect;         /* texels of the image it shows */
    double transform[6];  /* [a b c d e f]: screen = (a*u + c*v + e, b*u + d*v + f), (u, v) texels of rect from its top-left */
    float color[4];       /* multiplier, 0..1 */
    int blend;            /* dc_blend */
} dc_element;

/* An empty rect (set it to the texels shown), identity transform, white, alpha. */
DC_API void dc_element_default(dc_element* element);

typedef struct dc_scene dc_scene;

DC_API dc_status dc_scene_create(dc_viewport viewport, dc_scene** out);
DC_API void dc_scene_destroy(dc_scene* scene);
/* Registers an image by size; `path` (may be NULL) is what the mesh files
 * name, relative paths being relative to the working directory. Images
 * with the same path share draws. `*index` (may be NULL) gets its index. */
DC_API dc_status dc_scene_add_image(dc_scene* scene, const char* id, const char* path, int width, int height, uint32_t* index);
/* Appends an element in front of all earlier ones. `analysis` is the
 * analysis of the element's image and rect (its rect must equal
 * element->rect); the scene keeps a reference of its own, so the caller may
 * destroy the handle right away. Many elements may share one analysis. */
DC_API dc_status dc_scene_add_element(dc_scene* scene, const dc_element* element, const dc_analysis* analysis);
DC_API size_t dc_scene_element_count(const dc_scene* scene);

/* ---- Reconstruction (paper 2.3) into meshes */

typedef enum dc_graph_mode { DC_GRAPH_POLYGONS = 0, DC_GRAPH_BOXES = 1 } dc_graph_mode;
typedef enum dc_sort_method { DC_SORT_NONE = 0, DC_SORT_PAPER = 1, DC_SORT_BATCH = 2 } dc_sort_method;

typedef struct dc_reconstruct_options {
    int graph;                       /* dc_graph_mode; DC_GRAPH_POLYGONS */
    int sort;                        /* dc_sort_method; DC_SORT_BATCH */
    int opaque_polygons;             /* 0: no opaque pass at all; 1 */
    int64_t reserved_dynamic_levels; /* depth levels kept for dc_add_dynamic_elements; 0 */
    int cull_to_viewport;            /* drop elements outside the viewport; 0 */
    double texel_margin;             /* texels by which polygons keep clear of texel edges, so GL's vertex
                                        snapping cannot change a pixel (0..0.25); 1/32 */
} dc_reconstruct_options;

DC_API void dc_reconstruct_options_default(dc_reconstruct_options* options);

/* Draw calls in drawing order, with the scene's image list (docs/mesh-format.md). */
typedef struct dc_meshes dc_meshes;

typedef enum dc_pass {
    DC_PASS_OPAQUE = 0, /* depth test GL_GREATER, depth write on, blending off */
    DC_PASS_BLEND = 1   /* depth test GL_GREATER (when depth_test), depth write off, blending per draw */
} dc_pass;

/* One draw: a triangle list over DC_VERTEX_FLOATS floats per vertex:
 * x, y (screen pixels), z (0..1, larger nearer), u, v (0..1 of the whole
 * image), r, g, b, a (colour multiplier). 36-byte stride: position at
 * offset 0, uv at 12, colour at 20. */
#define DC_VERTEX_FLOATS 9
typedef struct dc_draw {
    uint32_t image;          /* index into the meshes' images */
    int pass;                /* dc_pass */
    int blend;               /* dc_blend */
    const float* vertices;   /* DC_VERTEX_FLOATS * vertex_count floats */
    size_t vertex_count;
    const uint32_t* indices; /* index_count indices (triangles) */
    size_t index_count;
} dc_draw;

typedef struct dc_meshes_stats {
    int64_t elements, draw_calls, triangles, depth_levels, graph_edges;
    int64_t depth_bits; /* depth buffer bits the z values need (<= 16 fits a 16-bit buffer) */
    double seconds;     /* reconstruction wall time: dc_reconstruct's own, or the file's (0: not measured); never written back */
} dc_meshes_stats;

typedef struct dc_meshes_info {
    dc_viewport viewport;
    int depth_test;     /* 0: draw everything with the depth test off */
    dc_meshes_stats stats;
} dc_meshes_info;

typedef struct dc_image_info {
    const char* id;
    const char* path;   /* as loaded: read files resolve it against the meshes file's directory */
    int width, height;
    int has_trans;      /* 1: texels of colour `trans` are transparent (a colour key the file does not hold) */
    uint32_t trans;     /* 0xRRGGBB */
} dc_image_info;

/* Reconstructs the scene; `options` NULL: the defaults. */
DC_API dc_status dc_reconstruct(const dc_scene* scene, const dc_reconstruct_options* options, dc_meshes** out);

/* An empty meshes object, to reuse as dc_add_dynamic_elements' frame. */
DC_API dc_status dc_meshes_create(dc_meshes** out);
DC_API void dc_meshes_destroy(dc_meshes* meshes);

/* Dynamic elements (beyond the paper): moving sprites drawn in front of a
 * static scene reconstructed with reserved_dynamic_levels = R, each frame,
 * without reconstructing it. `elements` (count <= R, painter's order) name
 * images of `scene` and have analyses[i] for element i (NULL allowed for
 * DC_BLEND_OPAQUE and DC_BLEND_MULTIPLY elements). `frame` (from
 * dc_meshes_create, reused frame after frame so its buffers are) receives
 * only the dynamic elements' draws, whose pass says where they go:
 *   1. the static opaque draws and the frame's opaque draws (any order:
 *      the depth test decides);
 *   2. the static blend draws, in order;
 *   3. the frame's blend draws, in order. */
DC_API dc_status dc_add_dynamic_elements(const dc_meshes* static_meshes, const dc_scene* scene, const dc_element* elements,
                                         const dc_analysis* const* analyses, size_t count, dc_meshes* frame);

DC_API dc_status dc_meshes_info_get(const dc_meshes* meshes, dc_meshes_info* out);
DC_API size_t dc_meshes_draw_count(const dc_meshes* meshes);
DC_API dc_status dc_meshes_draw(const dc_meshes* meshes, size_t i, dc_draw* out);
DC_API size_t dc_meshes_image_count(const dc_meshes* meshes);
DC_API dc_status dc_meshes_image(const dc_meshes* meshes, size_t i, dc_image_info* out);

/* Animations (Tiled's animated tiles; docs/mesh-format.md "animations" and
 * "animated"): frame 0 is what the vertices show. To show frame k, map the
 * u, v of each vertex of each animated run from frame 0's rect to frame
 * k's (same size; a frame of another image binds that texture). */
typedef struct dc_animation_frame {
    uint32_t image;   /* index into the meshes' images */
    dc_rect rect;     /* texels */
    int duration_ms;
} dc_animation_frame;
typedef struct dc_animated_run {
    uint32_t draw;          /* index into the draws */
    uint32_t first_vertex;  /* the run's vertices in that draw */
    uint32_t vertex_count;
    uint32_t animation;     /* index into the animations */
} dc_animated_run;
DC_API size_t dc_meshes_animation_count(const dc_meshes* meshes);
/* 0 for a NULL meshes or an animation index out of range. */
DC_API size_t dc_meshes_animation_frame_count(const dc_meshes* meshes, size_t animation);
DC_API dc_status dc_meshes_animation_frame(const dc_meshes* meshes, size_t animation, size_t frame, dc_animation_frame* out);
/* The runs in draw order. */
DC_API size_t dc_meshes_animated_run_count(const dc_meshes* meshes);
DC_API dc_status dc_meshes_animated_run(const dc_meshes* meshes, size_t i, dc_animated_run* out);

/* ---- Mesh files (docs/mesh-format.md) */

typedef enum dc_format { DC_FORMAT_JSON = 0, DC_FORMAT_BINARY = 1 } dc_format;

/* Flags of the writers. */
/* Kept for source compatibility: every write now does what it asked for.
 * Files the C API writes say stats.seconds 0 (a timing is not part of a
 * file the library writes: the same meshes are the same bytes on every
 * run); dc_meshes_info_get still reports the time. */
#define DC_WRITE_NO_TIMING 1u

/* Either form, told apart by the binary magic. */
DC_API dc_status dc_meshes_read_file(const char* path, dc_meshes** out);
/* From memory; relative image paths are resolved against `base_dir` (NULL
 * or "": kept as written). */
DC_API dc_status dc_meshes_read_memory(const void* data, size_t size, const char* base_dir, dc_meshes** out);
/* Atomic (a temporary file renamed over `path`); image paths are written
 * relative to the file's directory. "" and "-" are DC_ERROR_INVALID_ARGUMENT
 * (they name no file; the CLI's standard output is not the library's):
 * write "./-" for a file named "-", dc_meshes_write_memory for bytes. */
DC_API dc_status dc_meshes_write_file(const dc_meshes* meshes, const char* path, dc_format format, unsigned flags);
/* `*data` (release with dc_free) gets `*size` bytes; image paths as held. */
DC_API dc_status dc_meshes_write_memory(const dc_meshes* meshes, dc_format format, unsigned flags, void** data, size_t* size);
DC_API void dc_free(void* data);

/* ---- Moving sprites depth-culled every frame (depthcull/frame.h; since 0.2)
 *
 * An assembler holds pictures (a rect of a texture and its analysis, made
 * into templates once) and turns each frame's sprites, in painter's order,
 * into an opaque pass and a blend pass batched by texture where overlap
 * allows. Reuse one dc_frame: after the first frames (or
 * dc_assembler_reserve) assembling allocates nothing. Pure: no GL. */

typedef struct dc_assembler dc_assembler;
typedef struct dc_frame dc_frame;

typedef struct dc_sprite {
    uint32_t image;       /* dc_assembler_add_image id (ignored with an animation) */
    int32_t animation;    /* dc_assembler_add_animation id, or -1 */
    int32_t frame;        /* the animation's frame (modulo its count) */
    double transform[6];  /* as dc_element: each finite and within +-1e9 */
    float color[4];       /* as dc_element: each in 0..1 */
    int blend;            /* dc_blend */
} dc_sprite;

typedef struct dc_frame_stats {
    int64_t sprites, draw_calls, opaque_draws, triangles, blend_batches;
    int64_t over_budget; /* sprites treated as overlapping all (work bound), batching less */
} dc_frame_stats;

/* Identity transform, white, alpha, no animation. */
DC_API void dc_sprite_default(dc_sprite* sprite);
DC_API dc_status dc_assembler_create(dc_assembler** out);
DC_API void dc_assembler_destroy(dc_assembler* assembler);
/* A picture: `rect` of texture `texture` (the renderer's texture index, a
 * draw's image) of the given size, analysed by `analysis` (copied), which
 * must be the analysis of that same rect (DC_ERROR_INVALID_ARGUMENT
 * otherwise, as dc_scene_add_element). */
DC_API dc_status dc_assembler_add_image(dc_assembler* assembler, uint32_t texture, int texture_width, int texture_height,
                                        dc_rect rect, const dc_analysis* analysis, uint32_t* id);
/* An animation of `count` (at least 1) dc_assembler_add_image ids, shown
 * in turn. */
DC_API dc_status dc_assembler_add_animation(dc_assembler* assembler, const uint32_t* images, size_t count, uint32_t* id);
/* Grows the assembler's and `frame`'s buffers for frames of up to
 * `sprites` sprites, so that such frames allocate nothing. More than a
 * frame holds (2^21 - 1, one depth level each) is DC_ERROR_INVALID_ARGUMENT,
 * checked before anything is allocated. */
DC_API dc_status dc_assembler_reserve(dc_assembler* assembler, size_t sprites, dc_frame* frame);
DC_API dc_status dc_frame_create(dc_frame** out);
DC_API void dc_frame_destroy(dc_frame* frame);
/* A fully dynamic frame: `bounds` is the part of the world the overlap
 * test's grid covers (the camera's view). A sprite with an unknown picture
 * or animation, or a transform or colour value out of range (dc_sprite), is
 * DC_ERROR_INVALID_ARGUMENT, dc_last_error naming the sprite and field. */
DC_API dc_status dc_assemble(dc_assembler* assembler, const dc_sprite* sprites, size_t count, dc_viewport bounds, dc_frame* frame);
DC_API dc_status dc_frame_stats_get(const dc_frame* frame, dc_frame_stats* out);
/* The frame's vertices (9 floats each, as dc_draw) and indices, valid
 * until the frame is assembled again, for engines that draw it themselves. */
DC_API const float* dc_frame_vertices(const dc_frame* frame, size_t* vertex_count);
DC_API const uint32_t* dc_frame_indices(const dc_frame* frame, size_t* index_count);

/* ---- Sprites between the layers of a static scene: insertion points
 *
 * The frame loop (docs/engine-integration.md):
 *   once:  dc_scene_add_insertion_point between the dc_scene_add_element
 *          calls where moving sprites go (a game layer), dc_reconstruct,
 *          dc_renderer_set_meshes; an assembler with the sprites' pictures;
 *   each frame: dc_assemble_at with each point's sprites, then
 *          dc_renderer_draw_frame (or draw dc_frame_draw_get/dc_frame_point_get
 *          yourself). Static elements before a point stay behind its
 *          sprites, those after it in front, pixel for pixel as overpaint
 *          of all of them in layer order. */

typedef struct dc_insertion_point {
    size_t element;      /* sprites go before this element (the element count: on top of all) */
    int64_t levels;      /* depth levels reserved: at most this many sprites a frame */
    int64_t first_level; /* the first reserved level (reconstructed meshes) */
    uint32_t blend_draw; /* static draws from this one on are drawn after the point's sprites */
} dc_insertion_point;

/* Marks an insertion point before the next element added (after every
 * element added so far) with `levels` (0 .. 2^21 - 1, the most depth
 * levels) depth levels reserved for its sprites; points keep the order they are added in. dc_reconstruct
 * reserves them. */
DC_API dc_status dc_scene_add_insertion_point(dc_scene* scene, int64_t levels);
/* The insertion points of reconstructed meshes, in order. */
DC_API size_t dc_meshes_insertion_point_count(const dc_meshes* meshes);
DC_API dc_status dc_meshes_insertion_point(const dc_meshes* meshes, size_t i, dc_insertion_point* out);
/* Sprites at the insertion points of `static_meshes`: `sprites[k]` holds
 * `counts[k]` sprites (painter's order; NULL when 0) drawn at point k, for
 * k < `points` (at most the meshes' points; later points get none), each
 * list at most its point's levels. The frame's opaque draws go before the
 * static ones (the depth test orders them), point k's blend draws between
 * the static blend draws (dc_frame_point_get). Allocates nothing after the
 * first frames, as dc_assemble. */
DC_API dc_status dc_assemble_at(dc_assembler* assembler, const dc_meshes* static_meshes, const dc_sprite* const* sprites,
                                const size_t* counts, size_t points, dc_viewport bounds, dc_frame* frame);

/* An assembled frame's draws, for engines that draw it themselves: indices
 * [first_index, first_index + index_count) of dc_frame_indices, which index
 * dc_frame_vertices. Draws [0, opaque_draws of dc_frame_stats) are the
 * opaque pass, the rest blend draws grouped by point. */
typedef struct dc_frame_draw {
    uint32_t image; /* the texture (dc_assembler_add_image's `texture`) */
    int pass;       /* dc_pass */
    int blend;      /* dc_blend */
    uint32_t first_index, index_count;
} dc_frame_draw;
/* Where a point's blend draws go: the frame's draws [first_draw, end_draw)
 * after the static blend draws before static draw `static_draw` (static
 * draws from there on come after them). A fully dynamic frame has one
 * point, static_draw 0. */
typedef struct dc_frame_point {
    uint32_t static_draw, first_draw, end_draw;
} dc_frame_point;
DC_API size_t dc_frame_draw_count(const dc_frame* frame);
DC_API dc_status dc_frame_draw_get(const dc_frame* frame, size_t i, dc_frame_draw* out);
DC_API size_t dc_frame_point_count(const dc_frame* frame);
DC_API dc_status dc_frame_point_get(const dc_frame* frame, size_t i, dc_frame_point* out);

/* ---- The runtime renderer (depthcull::runtime) in the host's GL context
 *
 * Draws meshes the way an engine would: a plain sprite shader (texture x
 * vertex colour), opaque pass front to back with depth writes, blend pass
 * back to front, then each frame's dynamic draws. OpenGL 3.3 core or
 * OpenGL ES 3.0; the host owns the context (current on the calling thread)
 * and the framebuffer, which needs a depth buffer (24 bits for most scenes:
 * stats.depth_bits says). No EGL, no window, no GL loader library. */

/* A GL function as a loader returns it (cast to its own type to call it). */
typedef void (*dc_gl_function)(void);
/* Finds a GL entry point by name; NULL when absent. eglGetProcAddress and
 * glfwGetProcAddress have this type; SDL_GL_GetProcAddress (returning
 * void*) needs a one-line wrapper. Called only during dc_renderer_create. */
typedef dc_gl_function (*dc_gl_loader)(const char* name);

typedef struct dc_renderer dc_renderer;

/* Pixels of one image for dc_renderer_upload_images: RGBA8,
 * non-premultiplied, rows `stride` bytes apart. */
typedef struct dc_image_pixels {
    const uint8_t* rgba;
    int width, height;
    ptrdiff_t stride;
} dc_image_pixels;

/* What part of the world a frame shows: world [x, x+width) x [y, y+height)
 * fills the bound framebuffer's [0, width) x [0, height). flip_y: 1 for a
 * window's default framebuffer (row 0 at the bottom), 0 for an offscreen
 * one read back with glReadPixels (first row = the world's top row). */
typedef struct dc_camera {
    double x, y;
    int width, height;
    int flip_y;
} dc_camera;

typedef struct dc_frame_options {
    int clear_color;   /* clear the colour buffer to transparent black first; 0 */
    int count_samples; /* count fragments that pass the depth test (desktop GL only); 0 */
} dc_frame_options;

typedef struct dc_frame_counts {
    int64_t draw_calls, triangles;
    int64_t samples_passed; /* -1 unless count_samples on desktop GL */
} dc_frame_counts;

/* Builds the renderer in the current context; `loader` finds GL functions. */
DC_API dc_status dc_renderer_create(dc_gl_loader loader, dc_renderer** out);
/* Deletes the GL objects it made (context current); accepts NULL. */
DC_API void dc_renderer_destroy(dc_renderer* renderer);
/* "4.5 (Core Profile) Mesa 22.3.6"; valid while the renderer lives. */
DC_API const char* dc_renderer_gl_version(const dc_renderer* renderer);
/* One texture per image of the meshes (a draw's image indexes them):
 * either uploaded from pixels (copied into GL; sampled with `filter`, the
 * one the analysis assumed) or the host's own GL texture names (never
 * changed or deleted by the renderer). */
DC_API dc_status dc_renderer_upload_images(dc_renderer* renderer, const dc_image_pixels* images, size_t count, dc_filter filter);
DC_API dc_status dc_renderer_set_textures(dc_renderer* renderer, const unsigned* gl_texture_names, size_t count);
/* Uploads the static meshes once (after the textures); replaces any before. */
DC_API dc_status dc_renderer_set_meshes(dc_renderer* renderer, const dc_meshes* meshes);
/* Room for a frame's dynamic draws, so frames within it allocate nothing. */
DC_API dc_status dc_renderer_reserve_dynamic(dc_renderer* renderer, size_t vertices, size_t indices);
/* Draws one frame into the bound framebuffer: the static meshes and
 * `dynamic` (a frame from dc_add_dynamic_elements, or NULL) each in its
 * place. `options` and `counts` may be NULL. */
DC_API dc_status dc_renderer_draw(dc_renderer* renderer, const dc_camera* camera, const dc_meshes* dynamic,
                                  const dc_frame_options* options, dc_frame_counts* counts);

/* Draws the static meshes (dc_renderer_set_meshes; none set: nothing
 * static) and an assembled frame of moving sprites (since 0.2). */
DC_API dc_status dc_renderer_draw_frame(dc_renderer* renderer, const dc_camera* camera, const dc_frame* frame,
                                        const dc_frame_options* options, dc_frame_counts* counts);

#ifdef __cplusplus
}
#endif

#endif /* DEPTHCULL_H */

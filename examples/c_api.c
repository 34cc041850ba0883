/* The C API (include/depthcull/depthcull.h) from start to end, in C99:
 * analyze two sprites, build and reconstruct a small scene with room for
 * moving sprites, add them for a few frames, write the meshes in both
 * forms, read them back and check they are what was written.
 *
 *   c_api OUT_DIR
 *
 * Prints the figures of each step; exits non-zero on any failure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <depthcull/depthcull.h>

/* Stops the program with the library's message when a call fails. */
#define CHECK(call)                                                                              \
    do {                                                                                         \
        dc_status status_ = (call);                                                              \
        if (status_ != DC_OK) {                                                                  \
            fprintf(stderr, "c_api: %s: %s (%s)\n", #call, dc_last_error(), dc_status_string(status_)); \
            exit(1);                                                                             \
        }                                                                                        \
    } while (0)

/* A ball: transparent outside radius r, soft (partly transparent) rim one
 * texel wide, opaque inside: the case opaque polygons are for. */
static uint8_t* make_ball(int size) {
    uint8_t* rgba = calloc((size_t)size * size, 4);
    double c = size / 2.0, r = size / 2.0 - 1;
    int x, y;
    if (!rgba) exit(1);
    for (y = 0; y < size; ++y) {
        for (x = 0; x < size; ++x) {
            double d = hypot(x + 0.5 - c, y + 0.5 - c);
            uint8_t* p = rgba + ((size_t)y * size + x) * 4;
            p[0] = 200, p[1] = (uint8_t)(4 * x), p[2] = (uint8_t)(4 * y);
            p[3] = d > r ? 0 : d > r - 1 ? 128 : 255;
        }
    }
    return rgba;
}

static void print_analysis(const char* name, const dc_analysis* a) {
    dc_image_stats s;
    size_t i, points;
    CHECK(dc_analysis_stats(a, &s));
    printf("%s: %zu boundary polygon(s), %d vertices, area %.0f for %lld non-transparent texels (excess %.3f); "
           "%zu opaque polygon(s) cover %.1f%% of %lld opaque texels\n",
           name, dc_analysis_boundary_count(a), s.boundary_vertices, s.boundary_area, (long long)s.nontransparent_texels,
           s.nontransparent_texels ? s.boundary_area / (double)s.nontransparent_texels : 0.0, dc_analysis_opaque_count(a),
           100.0 * s.opaque_coverage, (long long)s.opaque_texels);
    for (i = 0; i < dc_analysis_boundary_count(a); ++i) {
        const dc_point* p = dc_analysis_boundary(a, i, &points);
        printf("  boundary %zu: %zu points, first (%g, %g)\n", i, points, p[0].x, p[0].y);
    }
}

/* Same draws, vertex for vertex. */
static int same_meshes(const dc_meshes* a, const dc_meshes* b) {
    size_t i, n = dc_meshes_draw_count(a);
    if (n != dc_meshes_draw_count(b)) return 0;
    for (i = 0; i < n; ++i) {
        dc_draw x, y;
        CHECK(dc_meshes_draw(a, i, &x));
        CHECK(dc_meshes_draw(b, i, &y));
        if (x.image != y.image || x.pass != y.pass || x.blend != y.blend || x.vertex_count != y.vertex_count ||
            x.index_count != y.index_count ||
            memcmp(x.vertices, y.vertices, x.vertex_count * DC_VERTEX_FLOATS * sizeof(float)) != 0 ||
            memcmp(x.indices, y.indices, x.index_count * sizeof(uint32_t)) != 0)
            return 0;
    }
    return 1;
}

int main(int argc, char** argv) {
    enum { kBall = 32, kMoving = 4 };
    char json_path[1024], bin_path[1024];
    uint8_t* ball_pixels;
    dc_analysis* ball;
    dc_scene* scene;
    dc_viewport viewport = {0, 0, 320, 240};
    dc_reconstruct_options options;
    dc_meshes *meshes, *frame, *from_json, *from_bin, *from_memory;
    dc_meshes_info info;
    dc_rect whole = {0, 0, kBall, kBall};
    uint32_t ball_image;
    void* bytes;
    size_t size;
    int i, f;

    if (argc < 2) {
        fprintf(stderr, "usage: %s OUT_DIR\n", argv[0]);
        return 2;
    }
    snprintf(json_path, sizeof json_path, "%s/meshes.json", argv[1]);
    snprintf(bin_path, sizeof bin_path, "%s/meshes.bin", argv[1]);

    /* 1. Per-image analysis: the pixels are only read during the call. */
    ball_pixels = make_ball(kBall);
    CHECK(dc_analyze_image(ball_pixels, kBall, kBall, kBall * 4, whole, NULL, &ball));
    free(ball_pixels);
    print_analysis("ball", ball);

    /* 2. A scene: 60 overlapping balls in painter's order. */
    CHECK(dc_scene_create(viewport, &scene));
    CHECK(dc_scene_add_image(scene, "ball", "ball.png", kBall, kBall, &ball_image));
    for (i = 0; i < 60; ++i) {
        dc_element e;
        dc_element_default(&e);
        e.image = ball_image;
        e.rect = whole;
        e.transform[4] = (i * 37) % 290;
        e.transform[5] = (i * 53) % 210;
        e.color[1] = (float)(i % 4) / 4.0f;
        e.blend = i % 10 == 9 ? DC_BLEND_ADD : DC_BLEND_ALPHA;
        CHECK(dc_scene_add_element(scene, &e, ball));
    }

    /* 3. Reconstruction (paper 2.3), keeping depth levels for moving sprites. */
    dc_reconstruct_options_default(&options);
    options.reserved_dynamic_levels = kMoving;
    CHECK(dc_reconstruct(scene, &options, &meshes));
    CHECK(dc_meshes_info_get(meshes, &info));
    printf("static scene: %lld elements -> %lld draw calls, %lld triangles, %lld depth levels, %lld graph edges, %lld depth bits\n",
           (long long)info.stats.elements, (long long)info.stats.draw_calls, (long long)info.stats.triangles,
           (long long)info.stats.depth_levels, (long long)info.stats.graph_edges, (long long)info.stats.depth_bits);

    /* 4. Each frame, moving sprites in front of it; `frame` is reused. */
    CHECK(dc_meshes_create(&frame));
    for (f = 0; f < 3; ++f) {
        dc_element moving[kMoving];
        const dc_analysis* analyses[kMoving];
        dc_meshes_info frame_info;
        size_t opaque = 0, d;
        for (i = 0; i < kMoving; ++i) {
            double angle = 0.5 * f + 1.5707963 * i;
            dc_element_default(&moving[i]);
            moving[i].image = ball_image;
            moving[i].rect = whole;
            moving[i].transform[4] = 144 + 100 * cos(angle);
            moving[i].transform[5] = 104 + 80 * sin(angle);
            analyses[i] = ball;
        }
        CHECK(dc_add_dynamic_elements(meshes, scene, moving, analyses, kMoving, frame));
        CHECK(dc_meshes_info_get(frame, &frame_info));
        for (d = 0; d < dc_meshes_draw_count(frame); ++d) {
            dc_draw draw;
            CHECK(dc_meshes_draw(frame, d, &draw));
            opaque += draw.pass == DC_PASS_OPAQUE;
        }
        printf("frame %d: %d moving sprites add %zu draws (%zu opaque, %zu blend), %lld triangles\n", f, kMoving,
               dc_meshes_draw_count(frame), opaque, dc_meshes_draw_count(frame) - opaque, (long long)frame_info.stats.triangles);
    }

    /* 5. Mesh files: write both forms, read them back, compare. */
    CHECK(dc_meshes_write_file(meshes, json_path, DC_FORMAT_JSON, DC_WRITE_NO_TIMING));
    CHECK(dc_meshes_write_file(meshes, bin_path, DC_FORMAT_BINARY, DC_WRITE_NO_TIMING));
    CHECK(dc_meshes_read_file(json_path, &from_json));
    CHECK(dc_meshes_read_file(bin_path, &from_bin));
    CHECK(dc_meshes_write_memory(from_bin, DC_FORMAT_BINARY, DC_WRITE_NO_TIMING, &bytes, &size));
    CHECK(dc_meshes_read_memory(bytes, size, NULL, &from_memory));
    printf("meshes: %zu draws; written to %s and %s; binary form %zu bytes\n", dc_meshes_draw_count(meshes), json_path, bin_path, size);
    dc_free(bytes);
    if (!same_meshes(meshes, from_json) || !same_meshes(meshes, from_bin) || !same_meshes(meshes, from_memory)) {
        fprintf(stderr, "c_api: meshes read back differ from those written\n");
        return 1;
    }
    printf("read back: JSON, binary and memory copies equal the written meshes\n");

    /* 6. Errors are statuses with a message, never a crash. */
    if (dc_meshes_read_memory("{\"viewport\": 1}", 15, NULL, &from_memory) != DC_ERROR_IO) return 1;
    printf("a bad file: %s\n", dc_last_error());

    dc_meshes_destroy(from_memory);
    dc_meshes_destroy(from_bin);
    dc_meshes_destroy(from_json);
    dc_meshes_destroy(frame);
    dc_meshes_destroy(meshes);
    dc_scene_destroy(scene);
    dc_analysis_destroy(ball);
    return 0;
}

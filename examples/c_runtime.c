/* The runtime renderer from C (include/depthcull/depthcull.h), hosted the
 * way an engine hosts it: the engine (here: headless EGL, surfaceless Mesa,
 * OpenGL 3.3 core, an offscreen framebuffer) owns the context and hands the
 * renderer its function loader. A scene of sprites is reconstructed once
 * with room for moving sprites, uploaded once, and drawn for a few frames
 * with the moving sprites added each frame.
 *
 *   c_runtime
 *
 * Prints the figures of each frame; exits 77 (skipped) when this machine
 * has no EGL context to offer, non-zero on any other failure. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <EGL/egl.h>
#include <EGL/eglext.h>
#include <GL/glcorearb.h>

#include <depthcull/depthcull.h>

#define CHECK(call)                                                                                      \
    do {                                                                                                 \
        dc_status status_ = (call);                                                                      \
        if (status_ != DC_OK) {                                                                          \
            fprintf(stderr, "c_runtime: %s: %s (%s)\n", #call, dc_last_error(), dc_status_string(status_)); \
            exit(1);                                                                                     \
        }                                                                                                \
    } while (0)

enum { kWidth = 320, kHeight = 240, kSprite = 32, kMoving = 6, kSkip = 77 };

/* The engine's side: a context current on this thread, with a framebuffer. */

static int host_context(void) {
    PFNEGLGETPLATFORMDISPLAYEXTPROC get_display = (PFNEGLGETPLATFORMDISPLAYEXTPROC)eglGetProcAddress("eglGetPlatformDisplayEXT");
    const EGLint config_attributes[] = {EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT, EGL_NONE};
    const EGLint context_attributes[] = {EGL_CONTEXT_MAJOR_VERSION, 3, EGL_CONTEXT_MINOR_VERSION, 3,
                                         EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT, EGL_NONE};
    EGLDisplay display;
    EGLConfig config = NULL;
    EGLContext context;
    EGLint major, minor, count = 0;
    if (!get_display) return 0;
    display = get_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, NULL);
    if (display == EGL_NO_DISPLAY || !eglInitialize(display, &major, &minor) || !eglBindAPI(EGL_OPENGL_API)) return 0;
    eglChooseConfig(display, config_attributes, &config, 1, &count); /* none needed with EGL_KHR_no_config_context */
    context = eglCreateContext(display, count ? config : NULL, EGL_NO_CONTEXT, context_attributes);
    return context != EGL_NO_CONTEXT && eglMakeCurrent(display, EGL_NO_SURFACE, EGL_NO_SURFACE, context);
}

static int host_framebuffer(int width, int height) {
    PFNGLGENFRAMEBUFFERSPROC gen_framebuffers = (PFNGLGENFRAMEBUFFERSPROC)eglGetProcAddress("glGenFramebuffers");
    PFNGLBINDFRAMEBUFFERPROC bind_framebuffer = (PFNGLBINDFRAMEBUFFERPROC)eglGetProcAddress("glBindFramebuffer");
    PFNGLGENRENDERBUFFERSPROC gen_renderbuffers = (PFNGLGENRENDERBUFFERSPROC)eglGetProcAddress("glGenRenderbuffers");
    PFNGLBINDRENDERBUFFERPROC bind_renderbuffer = (PFNGLBINDRENDERBUFFERPROC)eglGetProcAddress("glBindRenderbuffer");
    PFNGLRENDERBUFFERSTORAGEPROC storage = (PFNGLRENDERBUFFERSTORAGEPROC)eglGetProcAddress("glRenderbufferStorage");
    PFNGLFRAMEBUFFERRENDERBUFFERPROC attach = (PFNGLFRAMEBUFFERRENDERBUFFERPROC)eglGetProcAddress("glFramebufferRenderbuffer");
    PFNGLCHECKFRAMEBUFFERSTATUSPROC status = (PFNGLCHECKFRAMEBUFFERSTATUSPROC)eglGetProcAddress("glCheckFramebufferStatus");
    GLuint framebuffer, buffers[2];
    if (!gen_framebuffers || !bind_framebuffer || !gen_renderbuffers || !bind_renderbuffer || !storage || !attach || !status) return 0;
    gen_framebuffers(1, &framebuffer);
    gen_renderbuffers(2, buffers);
    bind_renderbuffer(GL_RENDERBUFFER, buffers[0]);
    storage(GL_RENDERBUFFER, GL_RGBA8, width, height);
    bind_renderbuffer(GL_RENDERBUFFER, buffers[1]);
    storage(GL_RENDERBUFFER, GL_DEPTH_COMPONENT24, width, height); /* the depth test is what culls */
    bind_framebuffer(GL_FRAMEBUFFER, framebuffer);
    attach(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_RENDERBUFFER, buffers[0]);
    attach(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_RENDERBUFFER, buffers[1]);
    return status(GL_FRAMEBUFFER) == GL_FRAMEBUFFER_COMPLETE;
}

/* A ball with a one-texel soft rim and an opaque core. */
static uint8_t* make_ball(void) {
    uint8_t* rgba = calloc(kSprite * kSprite, 4);
    double c = kSprite / 2.0, r = kSprite / 2.0 - 1;
    int x, y;
    if (!rgba) exit(1);
    for (y = 0; y < kSprite; ++y) {
        for (x = 0; x < kSprite; ++x) {
            double d = hypot(x + 0.5 - c, y + 0.5 - c);
            uint8_t* p = rgba + ((size_t)y * kSprite + x) * 4;
            p[0] = 230, p[1] = (uint8_t)(6 * x), p[2] = (uint8_t)(6 * y);
            p[3] = d > r ? 0 : d > r - 1 ? 128 : 255;
        }
    }
    return rgba;
}

int main(void) {
    dc_rect whole = {0, 0, kSprite, kSprite};
    dc_viewport viewport = {0, 0, kWidth, kHeight};
    dc_camera camera = {0, 0, kWidth, kHeight, 0};
    dc_frame_options options = {1, 1};
    dc_reconstruct_options reconstruct;
    dc_image_pixels pixels;
    dc_analysis* ball;
    dc_scene* scene;
    dc_meshes *meshes, *frame;
    dc_renderer* renderer;
    uint8_t* ball_pixels = make_ball();
    int i, f;

    if (!host_context() || !host_framebuffer(kWidth, kHeight)) {
        fprintf(stderr, "c_runtime: skipped: no headless OpenGL 3.3 context (EGL surfaceless)\n");
        return kSkip;
    }

    /* The asset build's part: analysis and reconstruction (usually read from
     * a meshes file with dc_meshes_read_file instead). */
    CHECK(dc_analyze_image(ball_pixels, kSprite, kSprite, kSprite * 4, whole, NULL, &ball));
    CHECK(dc_scene_create(viewport, &scene));
    CHECK(dc_scene_add_image(scene, "ball", "ball.png", kSprite, kSprite, NULL));
    for (i = 0; i < 200; ++i) {
        dc_element e;
        dc_element_default(&e);
        e.rect = whole;
        e.transform[4] = (i * 37) % (kWidth - kSprite);
        e.transform[5] = (i * 53) % (kHeight - kSprite);
        CHECK(dc_scene_add_element(scene, &e, ball));
    }
    dc_reconstruct_options_default(&reconstruct);
    reconstruct.reserved_dynamic_levels = kMoving;
    CHECK(dc_reconstruct(scene, &reconstruct, &meshes));

    /* The engine's part: textures and static meshes once, then frames. */
    CHECK(dc_renderer_create(eglGetProcAddress, &renderer));
    printf("runtime renderer on OpenGL %s\n", dc_renderer_gl_version(renderer));
    pixels.rgba = ball_pixels, pixels.width = kSprite, pixels.height = kSprite, pixels.stride = kSprite * 4;
    CHECK(dc_renderer_upload_images(renderer, &pixels, 1, DC_FILTER_NEAREST));
    free(ball_pixels); /* GL has its copy */
    CHECK(dc_renderer_set_meshes(renderer, meshes));
    CHECK(dc_renderer_reserve_dynamic(renderer, 4096, 16384));
    CHECK(dc_meshes_create(&frame));
    for (f = 0; f < 3; ++f) {
        dc_element moving[kMoving];
        const dc_analysis* analyses[kMoving];
        dc_frame_counts counts;
        for (i = 0; i < kMoving; ++i) {
            double angle = 0.3 * f + 6.2831853 * i / kMoving;
            dc_element_default(&moving[i]);
            moving[i].rect = whole;
            moving[i].transform[4] = kWidth / 2 - kSprite / 2 + 90 * cos(angle);
            moving[i].transform[5] = kHeight / 2 - kSprite / 2 + 70 * sin(angle);
            analyses[i] = ball;
        }
        CHECK(dc_add_dynamic_elements(meshes, scene, moving, analyses, kMoving, frame));
        CHECK(dc_renderer_draw(renderer, &camera, frame, &options, &counts));
        printf("frame %d: %lld draw calls, %lld triangles, %lld fragments shaded for %d pixels\n", f, (long long)counts.draw_calls,
               (long long)counts.triangles, (long long)counts.samples_passed, kWidth * kHeight);
    }

    /* What the depth test saved: the same scene without opaque polygons
     * shades every fragment of every sprite's boundary polygons. */
    {
        dc_meshes* plain;
        dc_frame_counts counts;
        reconstruct.opaque_polygons = 0;
        reconstruct.reserved_dynamic_levels = 0;
        CHECK(dc_reconstruct(scene, &reconstruct, &plain));
        CHECK(dc_renderer_set_meshes(renderer, plain));
        CHECK(dc_renderer_draw(renderer, &camera, NULL, &options, &counts));
        printf("without opaque polygons (static scene only): %lld draw calls, %lld fragments shaded\n", (long long)counts.draw_calls,
               (long long)counts.samples_passed);
        dc_meshes_destroy(plain);
    }

    dc_renderer_destroy(renderer); /* with the context still current */
    dc_meshes_destroy(frame);
    dc_meshes_destroy(meshes);
    dc_scene_destroy(scene);
    dc_analysis_destroy(ball);
    return 0;
}

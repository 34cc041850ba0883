/* A downstream C project: finds the installed depthcull with find_package
 * and reconstructs a one-element scene through the C API only (C99). */
#include <stdio.h>

#include <depthcull/depthcull.h>

int main(void) {
    uint8_t rgba[8 * 8 * 4] = {0};
    dc_rect rect = {0, 0, 8, 8};
    dc_viewport viewport = {0, 0, 16, 16};
    dc_analysis* analysis = NULL;
    dc_scene* scene = NULL;
    dc_meshes* meshes = NULL;
    dc_element e;
    int i;
    for (i = 2 * 8; i < 6 * 8; ++i) rgba[4 * i + 3] = 255; /* rows 2..5 opaque */
    dc_element_default(&e);
    e.rect = rect;
    if (dc_analyze_image(rgba, 8, 8, 32, rect, NULL, &analysis) != DC_OK || dc_scene_create(viewport, &scene) != DC_OK ||
        dc_scene_add_image(scene, "bar", "bar.png", 8, 8, NULL) != DC_OK || dc_scene_add_element(scene, &e, analysis) != DC_OK ||
        dc_reconstruct(scene, NULL, &meshes) != DC_OK) {
        fprintf(stderr, "consumer_c: %s\n", dc_last_error());
        return 1;
    }
    printf("C: 1 element -> %zu draws\n", dc_meshes_draw_count(meshes));
    i = dc_meshes_draw_count(meshes) == 0;
    dc_meshes_destroy(meshes);
    dc_scene_destroy(scene);
    dc_analysis_destroy(analysis);
    return i;
}

/*
 * Shadow-map matrices from C: the blocks of blocks.toml, one of its views, and a technique
 * by the command line's name; prints the maps as JSON (what `gnomon setup --json` prints for
 * the same scene file, view and technique, in part).
 *
 *   cargo build --release -p gnomon-c
 *   cc -std=c11 -I crates/gnomon-c/include examples/c/shadow_matrices.c \
 *       target/release/libgnomon_c.a -lm -lpthread -ldl -o shadow_matrices
 *   ./shadow_matrices cascades street "--cascades 3"
 */
#include <stdio.h>
#include <string.h>

#include "gnomon.h"

/* The blocks of blocks.toml: each block casts and receives; the ground only receives. */
static const GnomonBox BLOCKS[] = {
    {{-20, 0, -26}, {20, 16, -14}},  /* hall */
    {{20, 0, 4}, {28, 40, 12}},      /* tower */
    {{-23, 0, 3}, {-13, 8, 17}},     /* house */
    {{-30, 0, 29.5}, {30, 4, 30.5}}, /* wall */
    {{2.5, 0, 4.5}, {5.5, 3, 7.5}},  /* kiosk */
};
static const GnomonBox GROUND = {{-100, -5, -100}, {100, 0, 100}};
#define BLOCK_COUNT (sizeof BLOCKS / sizeof BLOCKS[0])

/* The views of blocks.toml, as `--view NAME` makes them (60 degrees, 16:9, near 1). */
static int view_named(const char *name, GnomonCamera *camera, GnomonLight *light) {
    GnomonCamera street = {{-30, 2, 60}, {10, 4, -10}, {0, 1, 0}, 60, 16.0 / 9.0, 1, 300};
    GnomonCamera overview = {{60, 50, 80}, {0, 0, 0}, {0, 1, 0}, 60, 16.0 / 9.0, 1, 400};
    GnomonLight sun = {GNOMON_LIGHT_SUN, {0, 0, 0}, {0.4, -0.8, -0.45}, 0, 0};
    if (strcmp(name, "street") == 0) {
        *camera = street;
    } else if (strcmp(name, "overview") == 0) {
        *camera = overview;
        sun.direction[0] = -0.3;
        sun.direction[1] = -1;
        sun.direction[2] = 0.2;
    } else {
        return 0;
    }
    *light = sun;
    return 1;
}

static void print_numbers(const char *key, const double *values, int count) {
    printf("\"%s\": [", key);
    for (int i = 0; i < count; i++) {
        printf("%s%.17g", i ? ", " : "", values[i]);
    }
    printf("]");
}

static void print_setup(const char *technique, const GnomonSetupResult *result) {
    const char *kinds[] = {"single", "plane", "cascades", "dual_paraboloid", "cube_faces"};
    printf("{\"technique\": \"%s\", \"fallback\": ", technique);
    if (result->fallback == GNOMON_FALLBACK_NONE) {
        printf("null");
    } else {
        printf("\"%s\"", gnomon_fallback_name(result->fallback));
    }
    printf(",\n \"selection\": {\"kind\": \"%s\"", kinds[result->selection.kind]);
    if (result->selection.kind == GNOMON_SELECTION_CASCADES) {
        printf(", ");
        print_numbers("view_depths", result->selection.view_depths,
                      (int)result->selection.cascade_count + 1);
    }
    printf("},\n \"maps\": [");
    for (uint32_t i = 0; i < result->map_count; i++) {
        const GnomonMap *map = &result->maps[i];
        printf("%s\n  {\"resolution\": %u, ", i ? "," : "", map->resolution);
        print_numbers("clip_from_world", map->clip_from_world, 16);
        printf(", ");
        print_numbers("depth_from_world", map->depth_from_world, 4);
        if (map->has_view_depth_range) {
            printf(", ");
            print_numbers("view_depth_range", map->view_depth_range, 2);
        }
        printf("}");
    }
    printf("]}\n");
}

int main(int argc, char **argv) {
    const char *technique = argc > 1 ? argv[1] : "lispsm";
    const char *view = argc > 2 ? argv[2] : "street";
    const char *options = argc > 3 ? argv[3] : "";
    GnomonCamera camera;
    GnomonLight light;
    if (!view_named(view, &camera, &light)) {
        fprintf(stderr, "error: unknown view '%s' (known: street, overview)\n", view);
        return 2;
    }

    GnomonBox receivers[BLOCK_COUNT + 1];
    receivers[0] = GROUND;
    memcpy(receivers + 1, BLOCKS, sizeof BLOCKS);
    GnomonScene *scene = NULL;
    if (gnomon_scene_new(BLOCKS, BLOCK_COUNT, receivers, BLOCK_COUNT + 1, &scene) != GNOMON_OK) {
        fprintf(stderr, "error: %s\n", gnomon_last_error_message());
        return 2;
    }

    GnomonSetupResult result;
    int status = gnomon_setup(scene, &camera, &light, technique, options, 2048, &result);
    if (status == GNOMON_OK) {
        print_setup(technique, &result);
    } else {
        fprintf(stderr, "error: %s\n", gnomon_last_error_message());
    }
    gnomon_scene_free(scene);
    return status == GNOMON_OK ? 0 : 2;
}

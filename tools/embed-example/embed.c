/* Embedding ntile: a world with a floor and a slope, a box and a ball dropped into
 * it, stepped at 40 Hz for 5 seconds. Build against an installed ntile with
 *
 *   cc -std=c11 embed.c $(pkg-config --cflags --libs ntile) -o embed
 *
 * It prints the bodies' positions every half second, then the box's resting place:
 * "box rests at X Y on_floor 0|1". `make check-install` builds it against a staged
 * install and checks that line (the floor's top is y = 480, the box's half-height 6).
 */
#include <stdio.h>
#include <ntile/ntile.h>

int main(void)
{
    if (nt_real_size() != (int)sizeof(nt_real)) {
        fprintf(stderr, "embed: compiled with a different NT_DOUBLE setting than libntile\n");
        return 1;
    }
    nt_world_def wd = nt_default_world_def(); /* 31 x 23 cells of 24 units, gravity (0, 320) */
    nt_world *world;
    nt_status st = nt_world_create(&wd, &world);
    if (st != NT_OK) {
        fprintf(stderr, "embed: nt_world_create: %s\n", nt_status_string(st));
        return 1;
    }
    for (int x = 0; x < 31; x++) nt_world_set_tile(world, x, 20, NT_TILE_FULL); /* floor: top at y = 480 */
    nt_world_set_tile(world, 20, 19, NT_TILE_45DEGnn);                          /* a slope rising to the right */
    for (int x = 21; x < 31; x++) nt_world_set_tile(world, x, 19, NT_TILE_FULL);

    nt_body_def bd = nt_default_body_def(); /* dynamic 12 x 12 box, mass 1 */
    bd.position = nt_v2(100, 100);
    nt_body_id box, ball;
    if ((st = nt_body_create(world, &bd, &box)) != NT_OK) goto fail;
    bd.shape = nt_shape_circle(8);
    bd.position = nt_v2(490, 300); /* falls onto the slope and rolls off to the left */
    if ((st = nt_body_create(world, &bd, &ball)) != NT_OK) goto fail;

    for (int step = 1; step <= 200; step++) {
        if ((st = nt_world_step(world, 1.0f / 40)) != NT_OK) goto fail;
        if (step % 20 == 0) {
            nt_vec2 a = nt_body_get_position(world, box), b = nt_body_get_position(world, ball);
            printf("t=%.2f box %.3f %.3f ball %.3f %.3f\n", step / 40.0, a.x, a.y, b.x, b.y);
        }
    }
    nt_body_tile_contacts tc;
    nt_body_get_tile_contacts(world, box, &tc);
    nt_vec2 p = nt_body_get_position(world, box);
    printf("box rests at %.3f %.3f on_floor %d\n", p.x, p.y, tc.on_floor ? 1 : 0);
    nt_world_destroy(world);
    return 0;
fail:
    fprintf(stderr, "embed: %s\n", nt_status_string(st));
    nt_world_destroy(world);
    return 1;
}

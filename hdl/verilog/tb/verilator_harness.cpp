// C interface to the Verilator model of window_network, for coopwin's --hdl verilator.
#include "Vwindow_network.h"
#include "verilated.h"
#include <cstdint>

#define UNIT(k)                                                                          \
    case k:                                                                              \
        m->coord_strobe_##k = (port >> 8) & 1;                                           \
        m->coord_data_##k = port & 0xff;                                                 \
        m->decimate_##k = (port >> 9) & 1;                                               \
        break;
#define OUT(k) \
    case k: return m->coord_ready_##k | (m->pixel_strobe_##k << 1) | (m->coord_error_##k << 2) | ((uint32_t)m->pixel_out_##k << 16);

static void set_port(Vwindow_network* m, int k, uint32_t port) {
    switch (k) { UNIT(0) UNIT(1) UNIT(2) UNIT(3) }
}
static uint32_t get_out(Vwindow_network* m, int k) {
    switch (k) { OUT(0) OUT(1) OUT(2) OUT(3) }
    return 0;
}

extern "C" {
void* wn_new() {
    auto* ctx = new VerilatedContext;
    auto* m = new Vwindow_network{ctx};
    m->clock = 0;
    m->reset = 0;
    m->eval();
    return m;
}
// cam: fval | lval << 1 | pixel_valid << 2 | pixel << 16 (up to 16 bits);
// ports[k]: data | strobe << 8 | decimate << 9.
// outs[k] after the rising edge: ready | strobe << 1 | error << 2 | pixel << 16.
void wn_step(void* p, uint32_t cam, const uint32_t* ports, uint32_t* outs) {
    auto* m = static_cast<Vwindow_network*>(p);
    m->fval = cam & 1;
    m->lval = (cam >> 1) & 1;
    m->pixel_valid = (cam >> 2) & 1;
    m->pixel = cam >> 16;
    for (int k = 0; k < 4; k++) set_port(m, k, ports[k]);
    m->clock = 0;
    m->eval();
    m->clock = 1;
    m->eval();
    for (int k = 0; k < 4; k++) outs[k] = get_out(m, k);
}
void wn_free(void* p) {
    auto* m = static_cast<Vwindow_network*>(p);
    auto* ctx = m->contextp();
    delete m;
    delete ctx;
}
}

// Verilator testbench for coopwin_soc (issue 40, item 3): feeds the camera input from raw
// 8-bit frames, takes the UART's bytes, and stops when the firmware exits (or at a cycle
// limit, as a failure). The camera: fval high from LEAD clocks before each frame's first line
// to the end of its last line, then VBLANK clocks low; lval high for a line's WIDTH pixels, a
// pixel every PIXEL_EVERY clocks, HBLANK clocks low between lines.
//
//   Vcoopwin_soc +firmware=fw.hex --frames DIR --count N --uart out.bin --log sim.log
//                [--every 12] [--vblank 80000] [--max-cycles C] [--vcd unit.vcd]
//
// (or --frames=DIR and so on, as FuseSoC passes them: hdl/soc/coopwin_soc.core's sim target).
//
// --vcd writes the window unit's signals in the layout `coopwin audit` reads (rust-hdl's: scope
// uut$0, its flags as start.q, strben.q and port.set_*.q), one pixel clock every 125,000 ps.
// A sample holds the unit's inputs as it sampled them on the edge and its registers after it.
//
// The defaults make a frame period of 874,632 clocks: 8.75 ms at a 100 MHz clock, the
// thesis's 114 frames/s camera (2.6).
#include "Vcoopwin_soc.h"
#include "Vcoopwin_soc___024root.h"
#include "Vcoopwin_soc_coopwin_soc.h"
#include "verilated.h"
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

static const int WIDTH = 256, HEIGHT = 256, LEAD = 8, HBLANK = 32;

// The window unit's trace for `coopwin audit` (testbench/src/analysis/audit/vcd.rs): value
// changes only, the clock's two edges a cycle.
struct UnitTrace {
    FILE* f = nullptr;
    std::vector<long long> last;
    static const unsigned long long PS = 125000;
    struct Var { const char* scope; const char* name; int width; };
    std::vector<Var> vars = {
        {"", "clock", 1}, {"", "fval", 1}, {"", "lval", 1}, {"", "coord_strobe", 1}, {"", "coord_data", 8},
        {"", "decimate", 1}, {"", "coord_ready", 1}, {"", "pixel_strobe", 1}, {"strben", "q", 1}, {"start", "q", 1},
        {"port.set_xn", "q", 8}, {"port.set_xx", "q", 8}, {"port.set_yn", "q", 8}, {"port.set_yx", "q", 8},
        {"port.set_dec", "q", 1},
    };
    bool open(const std::string& path) {
        f = std::fopen(path.c_str(), "w");
        if (!f) return false;
        std::fprintf(f, "$timescale 1ps $end\n$scope module uut$0 $end\n");
        // Scopes as paths ("port.set_xn"): close what the next variable's path leaves, open
        // what it adds.
        std::vector<std::string> open_path;
        auto split = [](const std::string& p) {
            std::vector<std::string> parts;
            size_t at = 0;
            while (!p.empty() && at <= p.size()) {
                size_t dot = p.find('.', at);
                parts.push_back(p.substr(at, dot == std::string::npos ? std::string::npos : dot - at));
                if (dot == std::string::npos) break;
                at = dot + 1;
            }
            return parts;
        };
        for (size_t i = 0; i <= vars.size(); i++) {
            std::vector<std::string> path = i < vars.size() ? split(vars[i].scope) : std::vector<std::string>();
            size_t common = 0;
            while (common < path.size() && common < open_path.size() && path[common] == open_path[common]) common++;
            for (size_t d = open_path.size(); d > common; d--) std::fprintf(f, "$upscope $end\n");
            for (size_t d = common; d < path.size(); d++) std::fprintf(f, "$scope module %s $end\n", path[d].c_str());
            open_path = path;
            if (i < vars.size()) std::fprintf(f, "$var wire %d v%zu %s $end\n", vars[i].width, i, vars[i].name);
        }
        std::fprintf(f, "$upscope $end\n$enddefinitions $end\n");
        last.assign(vars.size(), -1);
        return true;
    }
    void change(size_t i, long long v) {
        if (last[i] == v) return;
        last[i] = v;
        if (vars[i].width == 1) { std::fprintf(f, "%lldv%zu\n", v, i); return; }
        char bits[17];
        for (int b = 0; b < vars[i].width; b++) bits[b] = (v >> (vars[i].width - 1 - b)) & 1 ? '1' : '0';
        bits[vars[i].width] = 0;
        std::fprintf(f, "b%s v%zu\n", bits, i);
    }
    // `in`: the unit's inputs as it sampled them on edge `cyc`; the rest read after the edge.
    void sample(unsigned long long cyc, const long long in[5], Vcoopwin_soc* top) {
        auto* r = top->rootp;
        std::fprintf(f, "#%llu\n", cyc * PS);
        change(0, 1);
        for (int k = 0; k < 5; k++) change(1 + k, in[k]);
        change(6, r->coopwin_soc->coord_ready);
        change(7, r->coopwin_soc->pixel_strobe);
        change(8, r->coopwin_soc->unit__DOT__strben);
        change(9, r->coopwin_soc->unit__DOT__start);
        change(10, r->coopwin_soc->unit__DOT__set_xn);
        change(11, r->coopwin_soc->unit__DOT__set_xx);
        change(12, r->coopwin_soc->unit__DOT__set_yn);
        change(13, r->coopwin_soc->unit__DOT__set_yx);
        change(14, r->coopwin_soc->unit__DOT__set_dec);
        std::fprintf(f, "#%llu\n", cyc * PS + PS / 2);
        change(0, 0);
    }
};

static bool load_frame(const std::string& dir, int k, std::vector<unsigned char>& px) {
    char name[64];
    std::snprintf(name, sizeof name, "/frame%04d.raw", k);
    FILE* f = std::fopen((dir + name).c_str(), "rb");
    if (!f) return false;
    px.resize(WIDTH * HEIGHT);
    size_t n = std::fread(px.data(), 1, px.size(), f);
    std::fclose(f);
    return n == px.size();
}

int main(int argc, char** argv) {
    Verilated::commandArgs(argc, argv);
    std::string dir, uart_path = "uart.bin", log_path = "sim.log", vcd_path;
    int count = 20, every = 12;
    long vblank = 80000;
    unsigned long long max_cycles = 2000000000ULL;
    bool have_image = false;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i], value;
        // --name value (scripts/soc.sh) or --name=value (FuseSoC's cmdlinearg parameters).
        size_t eq = a.find('=');
        bool joined = a.rfind("--", 0) == 0 && eq != std::string::npos;
        if (joined) { value = a.substr(eq + 1); a.resize(eq); }
        auto next = [&]() { return joined ? value : i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--frames") dir = next();
        else if (a == "--count") count = std::atoi(next().c_str());
        else if (a == "--uart") uart_path = next();
        else if (a == "--log") log_path = next();
        else if (a == "--every") every = std::atoi(next().c_str());
        else if (a == "--vblank") vblank = std::atol(next().c_str());
        else if (a == "--max-cycles") max_cycles = std::strtoull(next().c_str(), nullptr, 10);
        else if (a == "--vcd") vcd_path = next();
        else if (a.rfind("+firmware=", 0) == 0) have_image = true;
        else { std::fprintf(stderr, "sim: unknown argument %s\n", a.c_str()); return 2; }
    }
    if (!have_image || dir.empty() || every < 1 || count < 1) {
        std::fprintf(stderr, "usage: %s +firmware=FILE --frames DIR [--count N] [--every K] ...\n", argv[0]);
        return 2;
    }
    std::vector<std::vector<unsigned char>> frames(count);
    for (int k = 0; k < count; k++)
        if (!load_frame(dir, k, frames[k])) {
            std::fprintf(stderr, "sim: cannot read %s/frame%04d.raw (%dx%d bytes)\n", dir.c_str(), k, WIDTH, HEIGHT);
            return 2;
        }
    FILE* uart = std::fopen(uart_path.c_str(), "wb");
    FILE* log = std::fopen(log_path.c_str(), "w");
    if (!uart || !log) { std::fprintf(stderr, "sim: cannot write %s or %s\n", uart_path.c_str(), log_path.c_str()); return 2; }

    Vcoopwin_soc* top = new Vcoopwin_soc;
    UnitTrace trace;
    if (!vcd_path.empty() && !trace.open(vcd_path)) { std::fprintf(stderr, "sim: cannot write %s\n", vcd_path.c_str()); return 2; }
    // Camera schedule, in clocks from the start of a frame period.
    const long line = (long)WIDTH * every + HBLANK;
    const long active = LEAD + (long)HEIGHT * line;
    const long period = active + vblank;
    std::fprintf(log, "camera %dx%d pixel_every=%d hblank=%d vblank=%ld frame_period=%ld clocks\n",
                 WIDTH, HEIGHT, every, HBLANK, vblank, period);
    unsigned long long cyc = 0;
    top->clk = 0;
    top->reset = 1;
    top->fval = 0; top->lval = 0; top->pixel = 0; top->pixel_valid = 0;
    // The first frame starts after a blanking period, so the firmware can arm it.
    const long start = vblank;
    int status = 1;
    bool at_line_start = true, irq_was = false;
    for (; cyc < max_cycles; cyc++) {
        if (cyc == 16) top->reset = 0;
        long t = (long)cyc - start;
        long f = t >= 0 ? t / period : -1, in = t >= 0 ? t % period : -1;
        bool fv = false, lv = false, pv = false;
        unsigned char p = 0;
        if (f >= 0 && f < count && in < active) {
            fv = true;
            if (in >= LEAD) {
                long r = (in - LEAD) / line, c = (in - LEAD) % line;
                if (c < (long)WIDTH * every) {
                    lv = true;
                    if (c % every == 0) { pv = true; p = frames[f][r * WIDTH + c / every]; }
                }
            }
        }
        top->fval = fv; top->lval = lv; top->pixel_valid = pv; top->pixel = p;
        // The unit's inputs as its registers will sample them on this edge.
        auto* r = top->rootp;
        long long sampled[5] = {(long long)fv, (long long)lv, r->coopwin_soc->coord_strobe, r->coopwin_soc->coord_data, r->coopwin_soc->coord_decimate};
        top->clk = 1;
        top->eval();
        if (trace.f) trace.sample(cyc, sampled, top);
        if (top->irq_window && !irq_was) std::fprintf(log, "irq %llu\n", cyc);
        irq_was = top->irq_window;
        if (top->uart_valid) {
            std::fputc(top->uart_data, uart);
            std::fprintf(log, "uart %llu %02x\n", cyc, top->uart_data);
        }
        if (top->console_valid) {
            if (top->console_data == '\n') std::fprintf(log, "\n");
            else if (at_line_start) std::fprintf(log, "fw %llu %c", cyc, top->console_data);
            else std::fputc(top->console_data, log);
            at_line_start = top->console_data == '\n';
        }
        if (top->halted) { status = top->exit_code; break; }
        top->clk = 0;
        top->eval();
        // After the last frame the firmware finishes its step (at most a few million clocks).
        if (f >= count && t - (long)count * period > 20000000L) {
            std::fprintf(log, "sim: the camera's %d frames ended 20,000,000 clocks ago and the firmware did not exit\n", count);
            break;
        }
    }
    // The lowest byte address the data bus wrote in RAM (the stack's deepest point).
    std::fprintf(log, "end cycle=%llu status=%d ram_low_write=0x%x\n", cyc, status, (unsigned)top->rootp->coopwin_soc->ram_low_write * 4);
    std::fclose(uart);
    std::fclose(log);
    if (trace.f) std::fclose(trace.f);
    top->final();
    delete top;
    return status;
}

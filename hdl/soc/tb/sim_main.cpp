// Verilator testbench for coopwin_soc (issue 40, item 3): feeds the camera input from raw
// 8-bit frames, takes the UART's bytes, and stops when the firmware exits (or at a cycle
// limit, as a failure). The camera: fval high from LEAD clocks before each frame's first line
// to the end of its last line, then VBLANK clocks low; lval high for a line's WIDTH pixels, a
// pixel every PIXEL_EVERY clocks, HBLANK clocks low between lines.
//
//   Vcoopwin_soc +firmware=fw.hex --frames DIR --count N --uart out.bin --log sim.log
//                [--every 12] [--vblank 80000] [--max-cycles C]
//
// The defaults make a frame period of 874,632 clocks: 8.75 ms at a 100 MHz clock, the
// thesis's 114 frames/s camera (2.6).
#include "Vcoopwin_soc.h"
#include "verilated.h"
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

static const int WIDTH = 256, HEIGHT = 256, LEAD = 8, HBLANK = 32;

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
    std::string dir, uart_path = "uart.bin", log_path = "sim.log";
    int count = 20, every = 12;
    long vblank = 80000;
    unsigned long long max_cycles = 2000000000ULL;
    bool have_image = false;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        auto next = [&]() { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--frames") dir = next();
        else if (a == "--count") count = std::atoi(next().c_str());
        else if (a == "--uart") uart_path = next();
        else if (a == "--log") log_path = next();
        else if (a == "--every") every = std::atoi(next().c_str());
        else if (a == "--vblank") vblank = std::atol(next().c_str());
        else if (a == "--max-cycles") max_cycles = std::strtoull(next().c_str(), nullptr, 10);
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
    bool at_line_start = true;
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
        top->clk = 1;
        top->eval();
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
        if (f >= count + 2) { std::fprintf(log, "sim: the camera's %d frames are over and the firmware did not exit\n", count); break; }
    }
    std::fprintf(log, "end cycle=%llu status=%d\n", cyc, status);
    std::fclose(uart);
    std::fclose(log);
    top->final();
    delete top;
    return status;
}

// coopwin_soc: the whole tracker on one chip (issue 40, item 1): a VexRiscv soft CPU
// (rv32imac, pythondata-cpu-vexriscv's VexRiscv_IMAC.v, Wishbone instruction and data buses),
// RAM, a UART and one window unit (hdl/verilog/window_unit.v) as a bus peripheral, with the
// camera input as the board tops have it (DVP: fval, lval, pixel, pixel_valid).
//
// One clock for the CPU, the bus, the unit and the camera: the camera's pixel rate is set by
// pixel_valid (a pixel every few clocks), so no crossing is needed here; a board with its own
// PCLK puts hdl/verilog/axil_cdc.v-style crossings between the domains (docs/soc.md).
//
// Memory map (the CPU caches addresses with bit 31 low; bit 31 high is uncached I/O):
//   0x0000_0000  RAM, RAM_BYTES, code and data (both buses)
//   0x8000_0000  UART: write = send a byte (the testbench takes it at once); read bit 0 = idle
//   0x8000_0004  exit: write the firmware's exit code (ends the simulation)
//   0x8000_0008  console: write a byte of the firmware's text lines (measurements)
//   0x8000_1000  window unit registers (see below)
//   0x9000_0000  window pixel RAM (PIX_BYTES, read-only to the CPU, one byte per word address
//                byte lane as written by the capture DMA: byte k at 0x9000_0000 + k)
//
// Window registers (word offsets from 0x8000_1000):
//   0x00 W  coordinate pins: bit 0 CSTRB1 (coord_strobe), bits 15:8 the byte, bit 16 decimate
//   0x04 R  status: bit 0 CRDY1 (coord_ready), bit 1 coord_error, bit 2 armed,
//           bit 3 window done (sticky), bit 4 set refused (sticky), bit 5 set accepted (sticky)
//   0x04 W  writing 1s clears the sticky bits 3..5
//   0x08 R  pixels the capture DMA wrote for the last window
//   0x0C R  frame number (fval rising edges since reset) of the last window done
//   0x10 R  cycle counter (free running)
//   0x14 R  cycle of the last window's done (its last pixel's clock + 1)
//   0x18 R  frame counter now
//   0x1C R  cycles the capture DMA held the pixel RAM's write port (pixels written, total)
//   0x20 R  cycles the instruction bus was busy (CYC & STB: a cache refill in progress)
//   0x24 R  cycles the data bus was busy (CYC & STB: a refill, a write-through, an I/O access)
//
// Capture DMA: every pixel the unit strobes is written into the pixel RAM at the next address
// on the same clock; the address restarts when a set is accepted. The camera cannot wait, so
// the pixels go to a RAM of their own, never through the CPU's bus (no bus arbitration); the
// CPU reads that RAM uncached, so no cache holds stale pixels.
// The interrupt line (window done, sticky) goes to the CPU's externalInterruptArray[0].
`timescale 1ns / 1ps
`default_nettype none

module coopwin_soc #(
    parameter integer RAM_BYTES = 1 << 18,  // program RAM (firmware/soc/memory.x: the firmware is linked for it)
    parameter integer PIX_BYTES = 1 << 16,  // window pixel RAM (a whole 256x256 frame)
    parameter integer WIDTH = 256,          // camera pixels per line
    parameter integer HEIGHT = 256,         // camera lines per frame
    parameter RAM_INIT = ""                 // program RAM image for a bitstream: byte lane k in RAM_INIT + "k" (soc_ram)
) (
    input  wire       clk,          // the one clock
    input  wire       reset,        // synchronous, active high
    input  wire       fval,         // camera frame valid (DVP VSYNC, as board tops invert it)
    input  wire       lval,         // camera line valid (DVP HREF)
    input  wire [7:0] pixel,        // camera pixel
    input  wire       pixel_valid,  // a pixel on `pixel` this clock
    output reg        uart_valid,   // a byte on uart_data this clock (the UART's line side is the testbench's)
    output reg  [7:0] uart_data,    // the byte sent
    output wire       irq_window,   // window done, sticky (the CPU's interrupt line)
    output reg        console_valid, // a console byte (the firmware's text lines) on console_data
    output reg  [7:0] console_data,  // the console byte
    output reg        halted,       // the firmware wrote the exit register (0x8000_0004)
    output reg  [7:0] exit_code     // its value: 0 for success
);
    localparam integer RAM_WORDS = RAM_BYTES / 4;
    localparam integer RAM_AW = $clog2(RAM_WORDS);
    localparam integer PIX_WORDS = PIX_BYTES / 4;
    localparam integer PIX_AW = $clog2(PIX_WORDS);

    // ---------------------------------------------------------------- CPU
    wire        i_cyc, i_stb, i_we;
    wire [29:0] i_adr;
    wire [31:0] i_dat_w;
    wire [3:0]  i_sel;
    wire [2:0]  i_cti;
    wire [1:0]  i_bte;
    reg         i_ack = 1'b0;
    wire [31:0] i_dat_r;
    wire        d_cyc, d_stb, d_we;
    wire [29:0] d_adr;
    wire [31:0] d_dat_w;
    wire [3:0]  d_sel;
    wire [2:0]  d_cti;
    wire [1:0]  d_bte;
    reg         d_ack = 1'b0;
    wire [31:0] d_dat_r;

    VexRiscv cpu (
        .externalResetVector(32'h0000_0000),
        .timerInterrupt(1'b0),
        .softwareInterrupt(1'b0),
        .externalInterruptArray({31'd0, irq_window}),
        .iBusWishbone_CYC(i_cyc), .iBusWishbone_STB(i_stb), .iBusWishbone_ACK(i_ack),
        .iBusWishbone_WE(i_we), .iBusWishbone_ADR(i_adr), .iBusWishbone_DAT_MISO(i_dat_r),
        .iBusWishbone_DAT_MOSI(i_dat_w), .iBusWishbone_SEL(i_sel), .iBusWishbone_ERR(1'b0),
        .iBusWishbone_CTI(i_cti), .iBusWishbone_BTE(i_bte),
        .dBusWishbone_CYC(d_cyc), .dBusWishbone_STB(d_stb), .dBusWishbone_ACK(d_ack),
        .dBusWishbone_WE(d_we), .dBusWishbone_ADR(d_adr), .dBusWishbone_DAT_MISO(d_dat_r),
        .dBusWishbone_DAT_MOSI(d_dat_w), .dBusWishbone_SEL(d_sel), .dBusWishbone_ERR(1'b0),
        .dBusWishbone_CTI(d_cti), .dBusWishbone_BTE(d_bte),
        .clk(clk), .reset(reset)
    );

    // ---------------------------------------------------------------- RAM (two ports)
    initial begin
        halted = 1'b0;
        exit_code = 8'd0;
    end
    // Instruction bus: a cache line's refill is an incrementing burst (CTI 010, the last beat
    // 111), one beat a clock: while a beat is acknowledged and more follow, the next word is
    // read ahead (the CPU moves to the next address as it takes the beat).
    wire i_more = i_ack & (i_cti == 3'b010);
    wire i_req = i_cyc & i_stb & (~i_ack | i_more);
    wire [RAM_AW-1:0] i_word = i_adr[RAM_AW-1:0] + {{(RAM_AW-1){1'b0}}, i_more};
    always @(posedge clk) i_ack <= i_req;

    // Data bus: one access a time, acknowledged the clock after it is seen.
    wire d_req = d_cyc & d_stb & ~d_ack;
    wire d_ram = d_adr[29:28] == 2'b00;                 // 0x0...
    wire d_uart = d_adr[29:10] == 20'h80000;            // 0x8000_0xxx (word address >> 2)
    wire d_win = d_adr[29:10] == 20'h80001;             // 0x8000_1xxx
    wire d_pix = d_adr[29:26] == 4'h9;                  // 0x9xxx_xxxx
    wire [RAM_AW-1:0] d_word = d_adr[RAM_AW-1:0];
    // The data read: a RAM's registered word or the I/O registers' value, chosen by where the
    // access went (registered with it), so each RAM keeps its own output register.
    reg         d_from_ram = 1'b0, d_from_pix = 1'b0;
    reg  [31:0] d_io_r = 32'd0;
    wire [31:0] ram_q, pix_q;
    wire        d_pix_read = d_req & ~d_ram & ~d_uart & ~d_win & d_pix;
    assign d_dat_r = d_from_ram ? ram_q : d_from_pix ? pix_q : d_io_r;
    // Port A the instruction bus (read only), port B the data bus. The firmware image is
    // INIT_FILE for a bitstream; the simulation loads +firmware=FILE instead.
    soc_ram #(.WORDS(RAM_WORDS), .INIT_FILE(RAM_INIT)) ram (
        .clk(clk), .a_en(i_req), .a_addr(i_word), .a_rdata(i_dat_r),
        .b_en(d_req & d_ram), .b_we(d_we ? d_sel : 4'd0), .b_addr(d_word), .b_wdata(d_dat_w),
        .b_rdata(ram_q)
    );
`ifndef SYNTHESIS
    // The image as 32-bit hex words, split into the RAM's byte lanes.
    reg [1023:0] image;
    reg [31:0]   image_words [0:RAM_WORDS-1];
    integer      w;
    initial if ($value$plusargs("firmware=%s", image)) begin
        for (w = 0; w < RAM_WORDS; w = w + 1) image_words[w] = 32'd0;
        $readmemh(image, image_words);
        for (w = 0; w < RAM_WORDS; w = w + 1) begin
            ram.lane[0].mem[w] = image_words[w][7:0];
            ram.lane[1].mem[w] = image_words[w][15:8];
            ram.lane[2].mem[w] = image_words[w][23:16];
            ram.lane[3].mem[w] = image_words[w][31:24];
        end
    end
    // The lowest RAM word the data bus wrote: the stack's deepest point while the image has no
    // .data or .bss (sim_main.cpp's end line; scripts/soc.sh checks it against the image's end).
    reg [RAM_AW-1:0] ram_low_write = {RAM_AW{1'b1}};
    always @(posedge clk) if (d_req && d_ram && d_we && d_word < ram_low_write) ram_low_write <= d_word;
`endif

    // ---------------------------------------------------------------- window unit
    reg         coord_strobe = 1'b0;
    reg  [7:0]  coord_data = 8'd0;
    reg         coord_decimate = 1'b0;
    wire        coord_ready, coord_error, armed, window_done, set_accepted, pixel_strobe;
    wire [7:0]  pixel_out;
    window_unit #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .PIXEL_BITS(8)) unit (
        .clock(clk), .fval(fval), .lval(lval), .pixel(pixel),
        .coord_strobe(coord_strobe), .coord_data(coord_data), .coord_ready(coord_ready),
        .decimate(coord_decimate), .pixel_strobe(pixel_strobe), .pixel_out(pixel_out),
        .coord_error(coord_error), .pixel_valid(pixel_valid), .reset(reset),
        .armed(armed), .window_done(window_done), .set_accepted(set_accepted)
    );

    // A set's last byte taken: accepted (set_accepted) or refused (coord_error rises then).
    reg         error_was = 1'b0;
    reg         done_flag = 1'b0, refused_flag = 1'b0, accepted_flag = 1'b0;
    reg  [31:0] cycle = 32'd0, done_cycle = 32'd0, dma_cycles = 32'd0;
    reg  [31:0] i_busy = 32'd0, d_busy = 32'd0;
    reg  [31:0] frames = 32'd0, done_frame = 32'd0;
    reg         fval_was = 1'b0;
    reg  [PIX_AW+1:0] pix_addr = 0, pix_count = 0;
    assign irq_window = done_flag;
    // The capture DMA writes one byte lane a strobe (port B); the data bus reads (port A).
    wire        dma_write = pixel_strobe & ~set_accepted;
    wire [31:0] pix_unused;
    soc_ram #(.WORDS(PIX_WORDS)) pix (
        .clk(clk), .a_en(d_pix_read), .a_addr(d_adr[PIX_AW-1:0]), .a_rdata(pix_q),
        .b_en(dma_write), .b_we(4'd1 << pix_addr[1:0]), .b_addr(pix_addr[PIX_AW+1:2]),
        .b_wdata({4{pixel_out}}), .b_rdata(pix_unused)
    );

    always @(posedge clk) begin
        cycle <= cycle + 32'd1;
        if (i_cyc & i_stb) i_busy <= i_busy + 32'd1;
        if (d_cyc & d_stb) d_busy <= d_busy + 32'd1;
        fval_was <= fval;
        if (fval & ~fval_was) frames <= frames + 32'd1;
        error_was <= coord_error;
        // The capture DMA: one byte lane of one word per strobe.
        if (set_accepted) begin
            pix_addr <= 0;
        end else if (pixel_strobe) begin
            pix_addr <= pix_addr + 1'b1;
            dma_cycles <= dma_cycles + 32'd1;
        end
        if (window_done) begin
            done_flag <= 1'b1;
            pix_count <= pix_addr + {{(PIX_AW + 1){1'b0}}, pixel_strobe};
            done_frame <= frames;
            done_cycle <= cycle;
        end
        if (set_accepted) accepted_flag <= 1'b1;
        if (coord_error & ~error_was) refused_flag <= 1'b1;
        // Bus side.
        d_ack <= d_req;
        uart_valid <= 1'b0;
        console_valid <= 1'b0;
        if (d_req) begin
            d_io_r <= 32'd0;
            d_from_ram <= d_ram;
            d_from_pix <= d_pix_read;
            if (d_ram) begin
                // soc_ram's port B
            end else if (d_uart) begin
                d_io_r <= 32'd1;
                if (d_we && d_adr[1:0] == 2'd1) begin
                    halted <= 1'b1;
                    exit_code <= d_dat_w[7:0];
                end else if (d_we && d_adr[1:0] == 2'd2) begin
                    console_valid <= 1'b1;
                    console_data <= d_dat_w[7:0];
                end else if (d_we) begin
                    uart_valid <= 1'b1;
                    uart_data <= d_sel[0] ? d_dat_w[7:0] : d_sel[1] ? d_dat_w[15:8] :
                                 d_sel[2] ? d_dat_w[23:16] : d_dat_w[31:24];
                end
            end else if (d_win) begin
                case (d_adr[3:0])
                    4'd0: d_io_r <= {15'd0, coord_decimate, coord_data, 7'd0, coord_strobe};
                    4'd1: d_io_r <= {26'd0, accepted_flag, refused_flag, done_flag, armed, coord_error, coord_ready};
                    4'd2: d_io_r <= {{(30-PIX_AW){1'b0}}, pix_count};
                    4'd3: d_io_r <= done_frame;
                    4'd4: d_io_r <= cycle;
                    4'd5: d_io_r <= done_cycle;
                    4'd6: d_io_r <= frames;
                    4'd7: d_io_r <= dma_cycles;
                    4'd8: d_io_r <= i_busy;
                    4'd9: d_io_r <= d_busy;
                    default: d_io_r <= 32'd0;
                endcase
                if (d_we && d_adr[3:0] == 4'd0) begin
                    coord_strobe <= d_dat_w[0];
                    coord_data <= d_dat_w[15:8];
                    coord_decimate <= d_dat_w[16];
                end
                if (d_we && d_adr[3:0] == 4'd1) begin
                    // Clears win over a new event on the same clock only for the bit written;
                    // the firmware clears before it starts the next set.
                    if (d_dat_w[3]) done_flag <= 1'b0;
                    if (d_dat_w[4]) refused_flag <= 1'b0;
                    if (d_dat_w[5]) accepted_flag <= 1'b0;
                end
            end
        end
        if (reset) begin
            coord_strobe <= 1'b0;
            done_flag <= 1'b0;
            refused_flag <= 1'b0;
            accepted_flag <= 1'b0;
            frames <= 32'd0;
            cycle <= 32'd0;
            dma_cycles <= 32'd0;
            i_busy <= 32'd0;
            d_busy <= 32'd0;
            pix_addr <= 0;
        end
    end

    // Unused by this SoC: the instruction bus only reads; the data bus's beats are taken one
    // by one (two clocks a beat), whatever its burst hints.
    wire unused = &{1'b0, pix_unused, i_we, i_dat_w, i_sel, i_bte, d_cti, d_bte, i_adr[29:RAM_AW]};
endmodule
`default_nettype wire

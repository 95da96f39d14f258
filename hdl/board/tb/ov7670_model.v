// OV7670-style DVP camera model for the board testbench (simulation only).
//
// PCLK free-running (its own oscillator, asynchronous to the board's 12 MHz; `running` = 0
// stops it). D, HREF and VSYNC change on PCLK's falling edge (OV7670 default, COM10 = 0).
// Frame timing as in the OV7670 datasheet's VGA frame (in lines of tLINE): VSYNC high for
// v_sync lines, v_back lines before the first HREF, v_active lines with HREF high for
// h_active pixels and low for h_blank, then v_front lines to the next VSYNC. VGA is
// 640/144 and 3/17/480/10 (784 x 510 tP); the testbench also uses smaller frames. One pixel
// is one PCLK in raw Bayer mode and two in RGB565 and YUV422 (tP = 2 tPCLK).
//
// The output format follows the SCCB registers written to the model, as on the sensor:
// COM7 (0x12) bit 2 RGB, bit 0 raw; COM15 (0x40) bits 5:4 = 01 with RGB is RGB565;
// COM7 = 0x00 is YUV422 (YUYV order, the default TSLB). COM7 bit 7 resets the registers.
// The format and geometry are taken at each frame's start.
//
// Pixel bytes are a fixed function of (frame, x, y, byte), `pix_byte`, so a testbench can
// compute any frame's window. `frame` counts frames started (VSYNC falling), from 0.
`timescale 1ns/1ps

module ov7670_model (
    output reg        pclk,
    output reg        vsync,
    output reg        href,
    output reg  [7:0] d,
    input  wire       xclk,
    input  wire       reset_n,
    input  wire       pwdn,
    input  wire       sioc,
    inout  wire       siod
);
    // Geometry and clock: the testbench may change these between frames.
    integer h_active = 80;
    integer h_blank = 24;
    integer v_sync = 3;
    integer v_back = 4;
    integer v_active = 60;
    integer v_front = 3;
    real    pclk_half = 20.5;       // ns: 24.4 MHz, unrelated to 12 MHz
    reg     running = 1'b1;
    // hold_vsync = 1: VSYNC stays high after its v_sync lines until it is cleared (`holding`
    // says the model waits), so a testbench can start a frame on a chosen PCLK edge: VSYNC
    // falls on the first falling edge after hold_vsync is cleared.
    reg     hold_vsync = 1'b0;
    reg     holding = 1'b0;

    integer frame = 0;              // frames started
    integer cur_frame = -1;         // the frame on D now (-1 before the first)
    integer fmt = 0;                // format of the frame in progress: 0 raw, 1 RGB565, 2 YUV

    // ---------------------------------------------------------------- SCCB slave (write only)
    pullup (siod);
    reg [7:0] regs [0:255];
    integer sccb_writes = 0;
    integer sccb_errors = 0;
    reg     sccb_on = 1'b0;
    integer sccb_n = 0;
    reg [27:0] sccb_sh = 28'd0;   // 27 bits, then the stop condition's SIOC rise
    integer i;
    task reset_regs;
        begin
            for (i = 0; i < 256; i = i + 1) regs[i] = 8'h00;
            regs[8'h12] = 8'h00;    // COM7: YUV
            regs[8'h40] = 8'hC0;    // COM15: RGB555/565 off, full range
        end
    endtask
    initial reset_regs;
    always @(negedge siod) if (sioc === 1'b1) begin   // start
        sccb_on = 1'b1; sccb_n = 0; sccb_sh = 28'd0;
    end
    always @(posedge sioc) if (sccb_on) begin
        sccb_sh = {sccb_sh[26:0], siod === 1'b0 ? 1'b0 : 1'b1};
        sccb_n = sccb_n + 1;
    end
    always @(posedge siod) if (sioc === 1'b1 && sccb_on) begin   // stop
        sccb_on = 1'b0;
        // A three-phase write: 27 clocks (id 0x42, X, reg, X, value, X) and the stop's.
        if (sccb_n == 28 && sccb_sh[27:20] == 8'h42) begin
            sccb_writes = sccb_writes + 1;
            if (sccb_sh[18:11] == 8'h12 && sccb_sh[9]) reset_regs;
            else regs[sccb_sh[18:11]] = sccb_sh[9:2];
        end else
            sccb_errors = sccb_errors + 1;
    end

    function integer format_of_regs(input [7:0] com7, input [7:0] com15);
        begin
            if (com7[2] == 1'b0 && com7[0] == 1'b1) format_of_regs = 0;            // raw Bayer
            else if (com7[2] == 1'b1 && com7[0] == 1'b0 && com15[5:4] == 2'b01) format_of_regs = 1;
            else if (com7[2:0] == 3'b000) format_of_regs = 2;                       // YUV422
            else format_of_regs = 3;                                                // unmodelled
        end
    endfunction

    // ---------------------------------------------------------------- pixel data
    function [7:0] pix_byte(input integer f, input integer x, input integer y, input integer k);
        integer v;
        begin
            v = x * 3 + y * 7 + f * 13 + k * 101 + ((x * y) >> 2) + (x >> 4) * 57;
            pix_byte = v[7:0];
        end
    endfunction

    // ---------------------------------------------------------------- timing
    initial begin pclk = 1'b0; vsync = 1'b1; href = 1'b0; d = 8'h00; end
    always begin
        #(pclk_half);
        if (running) pclk = ~pclk;
    end

    integer line, col, bpp, lbytes, nlines, ha, hb, vs, vb, va, vf;
    initial begin
        @(negedge pclk);
        forever begin
            // sample the registers and geometry for this frame
            ha = h_active; hb = h_blank; vs = v_sync; vb = v_back; va = v_active; vf = v_front;
            fmt = format_of_regs(regs[8'h12], regs[8'h40]);
            bpp = (fmt == 0) ? 1 : 2;
            lbytes = bpp * (ha + hb);
            // VSYNC lines
            vsync = 1'b1;
            repeat (vs * lbytes) @(negedge pclk);
            holding = 1'b1;
            while (hold_vsync) @(negedge pclk);
            holding = 1'b0;
            vsync = 1'b0;
            cur_frame = frame;
            frame = frame + 1;
            repeat (vb * lbytes) @(negedge pclk);
            for (line = 0; line < va; line = line + 1) begin
                for (col = 0; col < bpp * ha; col = col + 1) begin
                    href = 1'b1;
                    if (fmt == 0) d = pix_byte(cur_frame, col, line, 0);
                    else d = pix_byte(cur_frame, col / 2, line, col % 2);
                    @(negedge pclk);
                end
                href = 1'b0;
                d = 8'hxx;
                repeat (bpp * hb) @(negedge pclk);
                d = 8'h00;
            end
            repeat (vf * lbytes) @(negedge pclk);
        end
    end
endmodule

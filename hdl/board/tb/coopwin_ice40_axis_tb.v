// Self-checking simulation of coopwin_ice40_axis_top (the AXI4-Stream example integration)
// end to end: the OV7670 model on the camera pins, a host model on the UART pins. Icarus:
//   iverilog -g2005 -I hdl/board/tb -o tb.vvp -s coopwin_ice40_axis_tb \
//       hdl/verilog/window_unit_axis.v hdl/board/coopwin_dvp_axis.v hdl/board/coopwin_ice40_top.v \
//       hdl/board/coopwin_ice40_axis_top.v hdl/board/tb/ov7670_model.v hdl/board/tb/coopwin_ice40_axis_tb.v
//   vvp -n tb.vvp          (exit status 0 and "PASS" only if every check held)
// scripts/board-fpga.sh --axis runs it.
//
// The host plays the window processor over the UART only, as a PC would: it sets the camera
// to raw mode over SCCB, writes each window's X, Y, CTRL and COMMIT registers, polls STATUS
// until the window is finished, reads FRAMES, OVERFLOWS and the top's CAPTURED counters, then
// reads the captured pixels. The reference for every pixel is the camera model's pixel
// function (pix_byte) at the window's coordinates, for the frame the window came from: the
// first or second frame to start after the commit (which one depends on where in the frame
// the commit lands; the two differ in every pixel, so only one can match). Windows run two at
// once, overlapping, plain and decimated, at the frame's edges, with the output's tready
// following a pseudo-random bit (THROTTLE) and without; one run is made to overflow, and there
// every delivered pixel must still be the expected pixels in order with some left out, and
// delivered + OVERFLOWS must be the window's size.
`timescale 1ns/1ps

module coopwin_ice40_axis_tb;
    parameter integer WIDTH = 640;
    parameter integer HEIGHT = 480;
    localparam integer WINDOWS = 2;
    localparam integer FIFO_DEPTH = 32;
    localparam integer DEPTH = 2048;        // the top's BUF_AW = 11
    localparam real CLK12_HALF = 41.6667;   // 12 MHz
    localparam real BIT_NS = 1000.0 / 3.0;  // 3 Mbaud

    reg clk12 = 1'b0;
    always #(CLK12_HALF) clk12 = ~clk12;

    reg  host_tx = 1'b1;
    wire board_tx;
    wire pclk, vsync, href, xclk, rst_n, pwdn, sioc, siod;
    wire [7:0] d;
    wire [7:0] led;

    coopwin_ice40_axis_top #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .WINDOWS(WINDOWS),
                             .FIFO_DEPTH(FIFO_DEPTH)) dut (
        .clk12(clk12), .uart_rx(host_tx), .uart_tx(board_tx),
        .cam_pclk(pclk), .cam_vsync(vsync), .cam_href(href), .cam_d(d),
        .cam_xclk(xclk), .cam_reset_n(rst_n), .cam_pwdn(pwdn),
        .cam_sioc(sioc), .cam_siod(siod), .led(led));

    ov7670_model cam (
        .pclk(pclk), .vsync(vsync), .href(href), .d(d), .xclk(xclk),
        .reset_n(rst_n), .pwdn(pwdn), .sioc(sioc), .siod(siod));

    integer errors = 0;
    integer checks = 0;
    integer windows_done = 0;
    integer pixels_checked = 0;

`include "uart_host.vh"

    task check(input ok, input [8*80-1:0] what);
        begin
            checks = checks + 1;
            if (!ok) fail(what);
        end
    endtask

    // ------------------------------------------------------------------ the host protocol
    reg [7:0] b;
    task reg_write(input [15:0] a, input [31:0] v);
        begin
            host_send(8'h77); host_send(a[15:8]); host_send(a[7:0]);
            host_send(v[31:24]); host_send(v[23:16]); host_send(v[15:8]); host_send(v[7:0]);
            host_get(b, 1e5);
            check(b === 8'h4B, "register write not acknowledged");
        end
    endtask
    task reg_read(input [15:0] a, output [31:0] v);
        begin
            host_send(8'h72); host_send(a[15:8]); host_send(a[7:0]);
            host_get(v[31:24], 1e5); host_get(v[23:16], 1e5); host_get(v[15:8], 1e5); host_get(v[7:0], 1e5);
        end
    endtask
    task sccb_write(input [7:0] r, input [7:0] v);
        begin
            host_send(8'h53); host_send(r); host_send(v);
            host_get(b, 2e6);
            check(b === 8'h4B && cam.regs[r] === v && cam.sccb_errors == 0, "SCCB write");
        end
    endtask

    // Window k's registers (window_unit_axis's map) and the top's.
    function [15:0] wreg(input integer k, input integer off);
        wreg = 16'h20 * (k + 1) + off;
    endfunction
    localparam [15:0] X = 0, Y = 4, CTRL = 8, COMMIT = 12, STATUS = 16, FRAMES = 20, OVERFLOWS = 24;
    localparam [15:0] CAPTURED = 16'h1000, THROTTLE = 16'h1100;

    // ------------------------------------------------------------------ one run of windows
    // The windows of a run, set before calling run_windows: used[k] = 0 leaves window k idle.
    integer wx0 [0:WINDOWS-1], wx1 [0:WINDOWS-1], wy0 [0:WINDOWS-1], wy1 [0:WINDOWS-1];
    integer wdec [0:WINDOWS-1], used [0:WINDOWS-1];
    integer frames0 [0:WINDOWS-1], ovf0 [0:WINDOWS-1], fcommit [0:WINDOWS-1];
    reg [7:0] got [0:DEPTH-1];
    reg [31:0] v, st, cap;
    integer k, i, j, f, x, y, cols, rows, size, beats, drops, match, frame_of, t_poll;

    // The pixel the camera sent at (x, y) of frame f, in raw mode: the reference.
    function [7:0] ref_pixel(input integer f, input integer x, input integer y);
        ref_pixel = cam.pix_byte(f, x, y, 0);
    endfunction
    // The i-th pixel of window k in raster order (decimated: every second column and row).
    task window_pixel(input integer k, input integer i, output integer x, output integer y);
        integer step;
        begin
            step = wdec[k] ? 2 : 1;
            x = wx0[k] + step * (i % cols);
            y = wy0[k] + step * (i / cols);
        end
    endtask

    task run_windows(input [WINDOWS-1:0] throttle, input integer expect_overflow);
        begin
            for (k = 0; k < WINDOWS; k = k + 1) if (used[k]) begin
                reg_write(CAPTURED + 4 * k, 0);
                reg_read(wreg(k, FRAMES), v); frames0[k] = v;
                reg_read(wreg(k, OVERFLOWS), v); ovf0[k] = v;
            end
            reg_write(THROTTLE, throttle);
            for (k = 0; k < WINDOWS; k = k + 1) if (used[k]) begin
                reg_write(wreg(k, X), {wx1[k][15:0], wx0[k][15:0]});
                reg_write(wreg(k, Y), {wy1[k][15:0], wy0[k][15:0]});
                reg_write(wreg(k, CTRL), wdec[k]);
                reg_write(wreg(k, COMMIT), 0);
                fcommit[k] = cam.frame - 1;   // the frame on the pins when the commit was acknowledged
            end
            for (k = 0; k < WINDOWS; k = k + 1) if (used[k]) begin
                // Finished: neither armed nor busy (bits 0 and 1), within 4 frames.
                t_poll = $time;
                st = 32'd3;
                while ((st & 32'd3) != 0 && $time - t_poll < 4 * 7300 * 41) reg_read(wreg(k, STATUS), st);
                check((st & 32'd3) == 0, "window still armed or busy after 4 frames");
                check(st[3] == 1'b0, "a valid set was refused");
                cols = wdec[k] ? (wx1[k] - wx0[k]) / 2 + 1 : wx1[k] - wx0[k] + 1;
                rows = wdec[k] ? (wy1[k] - wy0[k]) / 2 + 1 : wy1[k] - wy0[k] + 1;
                size = cols * rows;
                reg_read(wreg(k, FRAMES), v);
                check(v == frames0[k] + 1, "FRAMES did not advance by one");
                reg_read(wreg(k, OVERFLOWS), v);
                drops = v - ovf0[k];
                check(st[4] == (drops > 0), "STATUS overflow bit disagrees with OVERFLOWS");
                check(expect_overflow ? drops > 0 : drops == 0, "overflows not as the run expects");
                reg_read(CAPTURED + 4 * k, cap);
                beats = cap[15:0];
                check(cap[31:28] == 4'd1, "not exactly one tuser beat");
                check(beats + drops == size, "delivered + overflows is not the window's size");
                if (drops == 0) check(cap[27:16] == rows, "tlast beats are not the window's rows");
                // The captured pixels.
                host_send(8'h42); host_send(k[7:0]); host_send(beats[15:8]); host_send(beats[7:0]);
                for (i = 0; i < beats; i = i + 1) host_get(got[i], 1e5);
                // Which frame: the first or second after the commit; all delivered pixels must
                // be the expected ones in order (with none left out unless beats were dropped).
                frame_of = -1;
                for (f = fcommit[k]; f <= fcommit[k] + 1; f = f + 1) begin
                    match = 1;
                    j = 0;
                    for (i = 0; i < beats && match; i = i + 1) begin
                        window_pixel(k, j, x, y);
                        while (drops > 0 && j < size - 1 && got[i] !== ref_pixel(f, x, y)) begin
                            j = j + 1;
                            window_pixel(k, j, x, y);
                        end
                        if (got[i] !== ref_pixel(f, x, y)) match = 0;
                        j = j + 1;
                    end
                    if (match && frame_of < 0) frame_of = f;
                end
                check(frame_of >= 0, "pixels are not the window of the first or second frame after the commit");
                if (frame_of < 0)
                    for (i = 0; i < beats && i < 8; i = i + 1) begin
                        window_pixel(k, i, x, y);
                        $display("    pixel %0d (%0d,%0d): got %h, frame %0d gives %h, frame %0d gives %h", i, x, y,
                                 got[i], fcommit[k], ref_pixel(fcommit[k], x, y), fcommit[k] + 1, ref_pixel(fcommit[k] + 1, x, y));
                    end
                pixels_checked = pixels_checked + beats;
                windows_done = windows_done + 1;
                $display("  window %0d x %0d..%0d y %0d..%0d%0s%0s: frame %0d, %0d of %0d pixels delivered, %0d overflows, %0d rows",
                         k, wx0[k], wx1[k], wy0[k], wy1[k], wdec[k] ? " decimated" : "", throttle[k] ? " throttled" : "",
                         frame_of, beats, size, drops, cap[27:16]);
            end
        end
    endtask

    task set_window(input integer k, input integer x0, input integer x1, input integer y0,
                    input integer y1, input integer dec);
        begin
            wx0[k] = x0; wx1[k] = x1; wy0[k] = y0; wy1[k] = y1; wdec[k] = dec; used[k] = 1;
        end
    endtask

    initial begin
        if ($test$plusargs("vcd")) begin
            $dumpfile("coopwin_ice40_axis_tb.vcd");
            $dumpvars(0, coopwin_ice40_axis_tb);
        end
        $display("coopwin_ice40_axis_tb: WIDTH %0d HEIGHT %0d, %0d windows, FIFO %0d, camera 80 x 60 raw frames",
                 WIDTH, HEIGHT, WINDOWS, FIFO_DEPTH);
        #2000;
        sccb_write(8'h12, 8'h01);            // COM7: raw Bayer, one byte a pixel
        reg_read(16'h0000, v);
        check(v == {FIFO_DEPTH[15:0], WINDOWS[15:0]}, "INFO register");
        reg_read(16'h0004, v);
        check(v == {HEIGHT[15:0], WIDTH[15:0]}, "GEOMETRY register");
        reg_write(16'h000C, 3);              // IRQ_ENABLE both windows
        for (k = 0; k < WINDOWS; k = k + 1) used[k] = 0;

        // Two overlapping windows, plain and decimated; both finished raise their IRQ bits.
        set_window(0, 10, 25, 5, 14, 0);
        set_window(1, 20, 39, 10, 19, 1);
        run_windows(2'b00, 0);
        reg_read(16'h0008, v);
        check(v == 3, "IRQ_STATUS: both windows done");
        check(led[1] === 1'b1, "irq (LED) not raised");
        reg_write(16'h0008, 3);
        reg_read(16'h0008, v);
        check(v == 0, "IRQ_STATUS not cleared by writing 1s");
        check(led[1] === 1'b0, "irq (LED) not cleared");
        reg_write(16'h000C, 0);
        // The same with tready gaps on both outputs: the FIFOs absorb them, nothing is lost.
        run_windows(2'b11, 0);
        // The frame's edges: its first two lines whole; its last two columns, two pixels a
        // row (a window is at least 2 x 2), with tready gaps.
        set_window(0, 0, 79, 0, 1, 0);
        set_window(1, 78, 79, 0, 59, 0);
        run_windows(2'b10, 0);
        // Decimated from an odd corner to an odd end; window 1 refused (xmin > xmax).
        set_window(0, 11, 30, 3, 12, 1);
        used[1] = 0;
        reg_write(wreg(1, X), {16'd20, 16'd30});
        reg_write(wreg(1, COMMIT), 0);
        reg_read(wreg(1, STATUS), v);
        check(v[3] == 1'b1 && v[2] == 1'b0, "an invalid set was not refused (STATUS invalid)");
        run_windows(2'b01, 0);
        // Whole 80-pixel rows into a 32-beat FIFO drained about every second clock: overflows,
        // counted, flagged, and every delivered pixel still in place.
        set_window(0, 0, 79, 20, 27, 0);
        run_windows(2'b01, 1);
        reg_write(wreg(0, STATUS), 32'h10);  // clear the sticky overflow bit
        reg_read(wreg(0, STATUS), v);
        check(v[4] == 1'b0, "STATUS overflow bit not cleared by writing 1");
        // Afterwards a window on the same output is whole again, without throttle.
        set_window(0, 5, 44, 40, 49, 0);
        run_windows(2'b00, 0);

        $display("coopwin_ice40_axis_tb: %0d windows, %0d pixels checked, %0d checks, %0d errors, UART framing errors %0d, %0.1f ms simulated",
                 windows_done, pixels_checked, checks, errors, rx_framing, $realtime / 1e6);
        if (errors == 0 && rx_framing == 0) begin
            $display("PASS");
            $finish;
        end else begin
            $display("FAIL");
            $finish_and_return(1);
        end
    end
endmodule

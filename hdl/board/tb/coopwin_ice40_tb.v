// Self-checking simulation of coopwin_ice40_top (the whole board top) with an OV7670 model
// on the camera pins and a host model on the UART pins. Icarus Verilog:
//   iverilog -g2005 -I hdl/board/tb -o tb.vvp -s coopwin_ice40_tb hdl/verilog/window_unit.v \
//       hdl/board/coopwin_ice40_top.v hdl/board/tb/ov7670_model.v hdl/board/tb/coopwin_ice40_tb.v
//   vvp -n tb.vvp          (exit status 0 and "PASS" only if every check held)
// scripts/board-fpga.sh runs it. Options (vvp plusargs): +novga skips the VGA-size frames,
// +vcd writes coopwin_ice40_tb.vcd.
//
// The host plays the processor exactly as a PC would over the FT2232H: it writes SCCB
// registers to choose the camera's format, writes windows ('W'), and checks each reply
// frame byte by byte against the window cut from the frame the board says it captured,
// computed from the camera model's pixel function. It also checks that this frame is the
// first or second one to start after the command's last byte (the set completes a few
// microseconds after it), the pixel count, the checksum, refused sets, truncation, and the
// timeout with the pixel clock stopped followed by recovery. In RTL simulation it also starts
// frames on chosen PCLK edges around the set's completion, to check that the board captures
// the frame window_unit arms: the set completed 0 clocks before the unit first sees fval high
// waits for the next frame; 1 or more clocks before, it arms this one.
`timescale 1ns/1ps

module coopwin_ice40_tb;
    parameter integer WIDTH = 640;          // the synthesised configuration
    parameter integer HEIGHT = 480;
    parameter integer BUF_AW = 12;
    parameter integer TIMEOUT_LOG2 = 20;    // 87 ms here (1.4 s on the board): > 2 VGA frames
    localparam integer DEPTH = 1 << BUF_AW;
    localparam real CLK12_HALF = 41.6667;   // 12 MHz
    localparam real BIT_NS = 1000.0 / 3.0;  // 3 Mbaud

    reg clk12 = 1'b0;
    always #(CLK12_HALF) clk12 = ~clk12;

    reg  host_tx = 1'b1;                    // host -> board (board uart_rx)
    wire board_tx;                          // board -> host
    wire pclk, vsync, href, xclk, rst_n, pwdn, sioc, siod;
    wire [7:0] d;
    wire [7:0] led;

    coopwin_ice40_top #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .BUF_AW(BUF_AW),
                        .TIMEOUT_LOG2(TIMEOUT_LOG2)) dut (
        .clk12(clk12), .uart_rx(host_tx), .uart_tx(board_tx),
        .cam_pclk(pclk), .cam_vsync(vsync), .cam_href(href), .cam_d(d),
        .cam_xclk(xclk), .cam_reset_n(rst_n), .cam_pwdn(pwdn),
        .cam_sioc(sioc), .cam_siod(siod), .led(led));

    ov7670_model cam (
        .pclk(pclk), .vsync(vsync), .href(href), .d(d), .xclk(xclk),
        .reset_n(rst_n), .pwdn(pwdn), .sioc(sioc), .siod(siod));

    integer errors = 0;
    integer checks = 0;
    // Frames started on a chosen edge (RTL simulation only): align_margin >= 0 holds VSYNC until
    // the set being written is about to complete, then releases it so that the unit first
    // samples fval high align_margin PCLK edges after the edge it takes the set's last byte.
    // margin_seen is the margin measured inside the unit (-1: not measured).
    integer align_margin = -1;
    integer margin_seen = -1;

    // ------------------------------------------------------------------ host UART
`include "uart_host.vh"

    // ------------------------------------------------------------------ reply frames
    reg [7:0] h [0:9];
    reg [7:0] chk, b;
    integer n, cnt, frame_no;
    task get_header(input real timeout_ns);
        integer k;
        begin
            for (k = 0; k < 10; k = k + 1) host_get(h[k], timeout_ns);
            chk = 8'h00;
            for (k = 2; k < 10; k = k + 1) chk = chk ^ h[k];
            if (h[0] !== 8'h43 || h[1] !== 8'h57) fail("frame magic is not 'CW'");
            cnt = {h[5], h[6], h[7]};
            n = {h[8], h[9]};
            frame_no = h[4];
        end
    endtask
    task get_checksum;
        begin
            host_get(b, 1e6);
            checks = checks + 1;
            if (b !== chk) fail("checksum");
        end
    endtask

    // ------------------------------------------------------------------ SCCB via the board
    task sccb_write(input [7:0] r, input [7:0] v);
        integer writes0;
        begin
            writes0 = cam.sccb_writes;
            host_send(8'h53); host_send(r); host_send(v);
            get_header(2e6);
            get_checksum;
            checks = checks + 1;
            if (h[2] !== 8'h10 || h[3] !== r || h[4] !== v || n != 0)
                fail("SCCB reply frame");
            if (cam.sccb_writes != writes0 + 1 || cam.sccb_errors != 0)
                fail("the camera did not decode exactly one SCCB write");
            if (!(r == 8'h12 && v[7]) && cam.regs[r] !== v) fail("camera register not written");
        end
    endtask

    task wait_frames(input integer k);
        integer f0;
        begin
            f0 = cam.frame;
            while (cam.frame < f0 + k) #1000;
        end
    endtask

    // ------------------------------------------------------------------ one window
    // mode: 0 raw, 1 RGB565, 2 YUV luma; expect: 0 window, 1 refused
    integer xs, ys, k, expected, got, bad, f_end, f_diff, f_cap, npix;
    reg [15:0] want;
    task window(input integer xmin, input integer xmax, input integer ymin, input integer ymax,
                input integer dec, input integer mode, input integer expect_refused);
        reg [7:0] flags;
        begin
            flags = {5'd0, mode[1:0], dec[0]};
            host_send(8'h57); host_send(flags);
            host_send(xmin[15:8]); host_send(xmin[7:0]); host_send(xmax[15:8]); host_send(xmax[7:0]);
            host_send(ymin[15:8]); host_send(ymin[7:0]); host_send(ymax[15:8]); host_send(ymax[7:0]);
            f_end = cam.frame;
            get_header(1.5e9 * 0.1);
            checks = checks + 1;
            if (h[3] !== flags) fail("flags echo");
            if (expect_refused) begin
                if (h[2] !== 8'h01 || cnt != 0 || n != 0) fail("an invalid set was not refused");
                get_checksum;
                $display("  window x %0d..%0d y %0d..%0d: refused, as expected", xmin, xmax, ymin, ymax);
            end else begin
                // the window's pixels, in raster order
                expected = (dec ? (xmax - xmin) / 2 + 1 : xmax - xmin + 1) *
                           (dec ? (ymax - ymin) / 2 + 1 : ymax - ymin + 1);
                if (cnt != expected) begin
                    fail("pixel count");
                    $display("    count %0d, expected %0d", cnt, expected);
                end
                if (h[2] !== (expected > DEPTH ? 8'h02 : 8'h00)) fail("frame type");
                if (n != (expected > DEPTH ? DEPTH : expected)) fail("pixels sent");
                // the frame the board captured: the first or second to start after the command
                f_diff = (frame_no - f_end % 256 + 256) % 256;
                if (f_diff > 1) begin
                    fail("captured frame is not the next one");
                    $display("    frame %0d, next frame %0d", frame_no, f_end % 256);
                end
                // a frame started on a chosen edge: the contract says which frame the unit arms
                if (align_margin >= 0) begin
                    checks = checks + 1;
                    if (margin_seen != align_margin) begin
                        fail("the frame did not start at the planned margin");
                        $display("    margin %0d clocks, planned %0d", margin_seen, align_margin);
                    end
                    if (f_diff != (align_margin >= 1 ? 0 : 1)) begin
                        fail("captured frame is not the one the unit arms");
                        $display("    margin %0d: frame %0d captured, the unit arms frame %0d",
                                 margin_seen, frame_no, f_end % 256 + (align_margin >= 1 ? 0 : 1));
                    end
                end
                f_cap = f_end + f_diff;
                bad = 0; npix = 0;
                for (ys = ymin; ys <= ymax; ys = ys + (dec ? 2 : 1))
                    for (xs = xmin; xs <= xmax; xs = xs + (dec ? 2 : 1)) begin
                        if (npix < n) begin
                            if (mode == 1)
                                want = {cam.pix_byte(f_cap, xs, ys, 0),
                                        cam.pix_byte(f_cap, xs, ys, 1)};
                            else
                                want = {8'h00, cam.pix_byte(f_cap, xs, ys, 0)};
                            if (mode == 1) begin
                                host_get(b, 1e6); got = b; chk = chk ^ b;
                                host_get(b, 1e6); got = got * 256 + b; chk = chk ^ b;
                            end else begin
                                host_get(b, 1e6); got = b; chk = chk ^ b;
                            end
                            if (got !== want) begin
                                if (bad < 5)
                                    $display("    pixel (%0d,%0d): got %h, expected %h", xs, ys, got, want);
                                bad = bad + 1;
                            end
                        end
                        npix = npix + 1;
                    end
                checks = checks + 1;
                if (bad != 0) fail("window pixels differ");
                get_checksum;
                if (align_margin >= 0)
                    $display("  window x %0d..%0d y %0d..%0d dec %0d mode %0d, set completed %0d clock(s) before fval: frame %0d (%0s), %0d pixels delivered, %0d sent, %0s",
                             xmin, xmax, ymin, ymax, dec, mode, margin_seen, f_cap,
                             f_diff == 0 ? "this frame" : "the next frame", cnt, n,
                             bad == 0 ? "all match" : "MISMATCH");
                else
                $display("  window x %0d..%0d y %0d..%0d dec %0d mode %0d: frame %0d, %0d pixels delivered, %0d sent%0s, %0s",
                         xmin, xmax, ymin, ymax, dec, mode, f_cap, cnt, n,
                         n < cnt ? " (truncated)" : "", bad == 0 ? "all match" : "MISMATCH");
            end
        end
    endtask

    task set_format(input integer mode);
        begin
            case (mode)
                0: sccb_write(8'h12, 8'h01);                              // raw Bayer RGB
                1: begin sccb_write(8'h12, 8'h04); sccb_write(8'h40, 8'hD0); end  // RGB565
                default: begin sccb_write(8'h12, 8'h00); sccb_write(8'h40, 8'hC0); end  // YUV
            endcase
            wait_frames(1);     // the camera takes a new format at a frame's start
        end
    endtask

    task geometry(input integer ha, input integer hb, input integer vs, input integer vb,
                  input integer va, input integer vf);
        begin
            cam.h_active = ha; cam.h_blank = hb; cam.v_sync = vs;
            cam.v_back = vb; cam.v_active = va; cam.v_front = vf;
            wait_frames(1);
        end
    endtask

`ifndef NETLIST
    // Frames started on a chosen edge. The set's last byte is taken on edge e0, where the
    // unit raises coord_ready: its strobe (c_req through sync_req's two flip-flops) rose at
    // e0-2, and sync_req's first flip-flop at e0-3. VSYNC released right after edge e0-3+m
    // falls on the next falling edge; the top registers it twice (fv0, fval1) and the unit
    // samples fval1 on e0+m. Measured: e0 (coord_ready rising with c_last) and the edge the
    // unit's FVC first rises at or after it.
    integer pedge = 0, e_set = -1, e_fval = -1, align_count = -1;
    reg s1_q = 1'b0, ready_tb = 1'b0, fvc_tb = 1'b0;
    always @(posedge pclk) begin
        #1;
        pedge = pedge + 1;
        if (dut.u_window.coord_ready && !ready_tb && dut.c_last) begin e_set = pedge; e_fval = -1; end
        if (dut.u_window.fvc && !fvc_tb && e_set >= 0 && e_fval < 0) begin
            e_fval = pedge;
            margin_seen = e_fval - e_set;
        end
        if (align_margin >= 0 && cam.hold_vsync) begin
            if (align_count < 0 && dut.sync_req.s1 && !s1_q && dut.c_last) align_count = align_margin;
            if (align_count == 0) begin cam.hold_vsync = 1'b0; align_count = -1; end
            else if (align_count > 0) align_count = align_count - 1;
        end
        s1_q = dut.sync_req.s1;
        ready_tb = dut.u_window.coord_ready;
        fvc_tb = dut.u_window.fvc;
    end

    // One window whose frame starts `m` clocks after the set completes (as the unit counts).
    task window_at_margin(input integer m, input integer xmin, input integer xmax,
                          input integer ymin, input integer ymax, input integer dec);
        begin
            cam.hold_vsync = 1'b1;
            wait (cam.holding);
            align_margin = m; margin_seen = -1; e_set = -1;
            window(xmin, xmax, ymin, ymax, dec, 0, 0);
            align_margin = -1;
            if (cam.hold_vsync) begin fail("VSYNC was never released"); cam.hold_vsync = 1'b0; end
        end
    endtask

    // +trace: the board's pixel-clock events, for debugging (not in a netlist simulation).
    reg trace = 1'b0;
    initial trace = $test$plusargs("trace");
    always @(posedge pclk) if (trace) begin
        if (dut.set_done) $display("    trace %0t: set complete (camera frame %0d started so far)", $time, cam.frame);
        if (dut.fval_rise) $display("    trace %0t: fval rises, board frame %0d, state %0d", $time, dut.frame_cnt, dut.pst);
    end
`endif

    real t_start;
    initial begin
        if ($test$plusargs("vcd")) begin
            $dumpfile("coopwin_ice40_tb.vcd");
            $dumpvars(0, coopwin_ice40_tb);
        end
        t_start = $realtime;
        #2000;
        $display("coopwin_ice40_tb: WIDTH %0d HEIGHT %0d, buffer %0d pixels, PCLK %0.1f MHz, clk12 12 MHz, 3 Mbaud",
                 WIDTH, HEIGHT, DEPTH, 500.0 / cam.pclk_half);

        $display("small frames (80 x 60):");
        set_format(0);
        window(10, 25, 5, 14, 0, 0, 0);
        window(3, 20, 2, 11, 1, 0, 0);             // decimated, odd anchor
        window(0, 79, 0, 2, 0, 0, 0);              // whole lines from column 0
        window(60, 79, 50, 59, 0, 0, 0);           // last column and last line
        window(7, 8, 9, 10, 1, 0, 0);              // 2 x 2 decimated: one pixel
        window(30, 30, 5, 9, 0, 0, 1);             // xmin = xmax: refused
        window(5, 9, 20, 10, 0, 0, 1);             // ymin > ymax: refused
        window(0, WIDTH, 0, 9, 0, 0, 1);           // xmax = WIDTH: refused
        window(0, 79, 0, 59, 0, 0, 0);             // 4800 pixels: more than the buffer
        window(0, 79, 0, 59, 1, 0, 0);             // decimated: 1200 pixels

        set_format(1);
        window(5, 40, 3, 20, 0, 1, 0);             // RGB565, 16-bit pixels
        window(0, 79, 40, 59, 1, 1, 0);

        set_format(2);
        window(17, 62, 11, 31, 0, 2, 0);           // YUV422, luma

        // Timeout: PCLK stopped, so the bytes are never taken. Then PCLK runs again and the
        // next window must work (the pixel-clock domain was reset).
        set_format(0);
        cam.running = 1'b0;
        host_send(8'h57); host_send(8'h00);
        host_send(0); host_send(10); host_send(0); host_send(20);
        host_send(0); host_send(10); host_send(0); host_send(20);
        get_header(0.2e9);
        get_checksum;
        checks = checks + 1;
        if (h[2] !== 8'h03) fail("no timeout frame with PCLK stopped");
        else $display("  PCLK stopped: timeout frame after %0.1f ms", 1.0 * (1 << TIMEOUT_LOG2) / 12000.0);
        #100000;
        cam.running = 1'b1;
        window(10, 25, 5, 14, 0, 0, 0);
        window(40, 41, 40, 41, 0, 0, 0);

`ifndef NETLIST
        // Frames that start on chosen edges around the set's completion: 0 clocks (the unit
        // arms the next frame), 1 (the first that arms this frame), 2, 3.
        window_at_margin(0, 0, 9, 0, 3, 0);
        window_at_margin(1, 0, 9, 0, 3, 0);
        window_at_margin(2, 4, 13, 2, 5, 1);
        window_at_margin(3, 70, 79, 56, 59, 0);
        window_at_margin(1, 0, 79, 0, 1, 0);
`endif

        // Bytes that are not commands are dropped.
        host_send(8'hAA); host_send(8'h00); host_send(8'hFF);
        window(20, 35, 20, 35, 1, 0, 0);
        if (WIDTH <= 256 && HEIGHT <= 256) begin
            $display("4-byte coordinates (WIDTH and HEIGHT <= 256):");
            window(10, 266, 0, 5, 0, 0, 1);        // a high byte: cannot be sent, refused
            window(10, 20, 0, 5, 0, 0, 0);
        end

        if (!$test$plusargs("novga") && WIDTH >= 640 && HEIGHT >= 480) begin
            $display("VGA frames (640 x 480, OV7670 VGA timing 784 x 510 tP):");
            geometry(640, 144, 3, 17, 480, 10);
            window(600, 639, 440, 479, 0, 0, 0);   // bottom-right corner, coordinates > 255
            window(200, 330, 250, 262, 1, 0, 0);   // across 256, decimated
            set_format(1);
            window(590, 639, 0, 9, 0, 1, 0);       // RGB565: the last pixels of 1280-byte lines
        end

        $display("coopwin_ice40_tb: %0d checks, %0d errors, UART framing errors %0d, SCCB errors %0d, %0.1f ms simulated",
                 checks, errors, rx_framing, cam.sccb_errors, ($realtime - t_start) / 1e6);
        if (errors == 0 && rx_framing == 0 && cam.sccb_errors == 0) begin
            $display("PASS");
            $finish;
        end else begin
            $display("FAIL");
            $finish_and_return(1);
        end
    end
endmodule

// coopwin_soc_ulx3s: the SoC (hdl/soc/coopwin_soc.v) on a ULX3S (LFE5U-85F, CABGA381) with an
// OV7670-style DVP camera on header J1 and the position updates on the FTDI UART.
// Pins: hdl/soc/ulx3s/coopwin_soc_ulx3s.lpf. Build: scripts/soc-ecp5.sh.
// Synthesised, placed, routed and packed only: NOT run on hardware.
//
// One clock: the board's 25 MHz oscillator runs the whole SoC (below its measured Fmax, see
// docs/synthesis.md). The camera is oversampled: PCLK, VSYNC, HREF and D pass two flip-flops
// and a pixel is taken on PCLK's synchronised rising edge, which needs PCLK under about a
// quarter of the clock (6 MHz here); the SoC's `pixel_valid` contract is exactly that.
// The UART bytes (16 a position update, written back to back) queue in a 16-byte FIFO and
// leave at 1 Mbaud (25 clocks a bit, 8N1); the console and exit registers go nowhere.
`timescale 1ns / 1ps
`default_nettype none

module coopwin_soc_ulx3s #(
    parameter RAM_INIT = "",             // the firmware image's byte-lane files (soc_ram)
    parameter integer RAM_BYTES = 1 << 18 // program RAM (256 KiB: the image and its stack fit)
) (
    input  wire       clk_25mhz,   // G2: the board's oscillator, the SoC's clock
    input  wire       cam_pclk,    // J1 GP0: camera pixel clock (sampled, not a clock here)
    input  wire       cam_vsync,   // J1 GN0: camera VSYNC (high between frames)
    input  wire       cam_href,    // J1 GP1: camera HREF (line valid)
    input  wire [7:0] cam_d,       // J1 GN1..GP5: camera data
    output wire       ftdi_rxd,    // L4: UART to the host (the FTDI's RXD)
    output wire [7:0] led          // LEDs: bit 0 window done, bit 1 halted, 7:2 uart activity
);
    // Power-on reset: 16 clocks.
    reg [4:0] por = 5'd0;
    wire reset = ~por[4];
    always @(posedge clk_25mhz) if (~por[4]) por <= por + 5'd1;

    // The camera, synchronised (two flip-flops each), a pixel on PCLK's rising edge.
    (* async_reg = "true" *) reg [10:0] cam_s1 = 11'd0;
    (* async_reg = "true" *) reg [10:0] cam_s2 = 11'd0;
    reg pclk_was = 1'b0;
    always @(posedge clk_25mhz) begin
        cam_s1 <= {cam_pclk, cam_vsync, cam_href, cam_d};
        cam_s2 <= cam_s1;
        pclk_was <= cam_s2[10];
    end
    wire pixel_valid = cam_s2[10] & ~pclk_was & cam_s2[8];

    wire       uart_valid, irq_window, console_valid, halted;
    wire [7:0] uart_data, console_data, exit_code;
    coopwin_soc #(.RAM_BYTES(RAM_BYTES), .RAM_INIT(RAM_INIT)) soc (
        .clk(clk_25mhz), .reset(reset),
        .fval(~cam_s2[9]), .lval(cam_s2[8]), .pixel(cam_s2[7:0]), .pixel_valid(pixel_valid),
        .uart_valid(uart_valid), .uart_data(uart_data), .irq_window(irq_window),
        .console_valid(console_valid), .console_data(console_data),
        .halted(halted), .exit_code(exit_code)
    );

    // 16-byte FIFO and the serialiser (1 Mbaud at 25 MHz).
    reg [7:0] fifo [0:15];
    reg [4:0] wr = 5'd0, rd = 5'd0;
    reg [9:0] sh = 10'h3FF;               // {stop, data, start} shifted out LSB first; idle high
    reg [3:0] left = 4'd0;                // bits still to send
    reg [4:0] cnt = 5'd0;
    always @(posedge clk_25mhz) begin
        if (uart_valid && (wr - rd) != 5'd16) begin
            fifo[wr[3:0]] <= uart_data;
            wr <= wr + 5'd1;
        end
        if (left == 4'd0) begin
            if (wr != rd) begin
                sh <= {1'b1, fifo[rd[3:0]], 1'b0};
                rd <= rd + 5'd1;
                left <= 4'd10;
                cnt <= 5'd24;
            end
        end else if (cnt != 5'd0) begin
            cnt <= cnt - 5'd1;
        end else begin
            cnt <= 5'd24;
            sh <= {1'b1, sh[9:1]};
            left <= left - 4'd1;
        end
    end
    assign ftdi_rxd = sh[0];
    assign led = {wr[4:0] != rd[4:0], rd[3:0], 1'b0, halted, irq_window};
    wire unused = &{1'b0, console_valid, console_data, exit_code};
endmodule
`default_nettype wire

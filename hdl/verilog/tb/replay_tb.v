`timescale 1ns/1ps
// Replays a stimulus recorded from the rust-hdl simulation into window_unit, one line per
// pixel clock, hex fields separated by spaces:
//   fval lval pixel_valid pixel reset coord_strobe coord_data decimate
// After each rising edge it writes the outputs as one line:
//   coord_ready pixel_strobe pixel_out coord_error
// Usage (Icarus):    iverilog -g2012 -P replay_tb.WIDTH=640 ... -o r.vvp replay_tb.v window_unit.v
//                    vvp -n r.vvp +stim=IN.txt +out=OUT.txt
// Usage (Verilator): verilator --binary --timing -GWIDTH=640 ... --top-module replay_tb ...
`default_nettype none
module replay_tb #(
    parameter integer WIDTH = 256,
    parameter integer HEIGHT = 256,
    parameter integer PIXEL_BITS = 8
);
  reg clock = 0;
  reg fval = 0, lval = 0, pixel_valid = 0, reset = 0, coord_strobe = 0, decimate = 0;
  reg [PIXEL_BITS-1:0] pixel = 0;
  reg [7:0] coord_data = 0;
  wire coord_ready, pixel_strobe, coord_error;
  wire [PIXEL_BITS-1:0] pixel_out;
  integer fin, fout, fields;
  integer f_fval, f_lval, f_valid, f_pixel, f_reset, f_strobe, f_data, f_decimate;
  reg [8*1024-1:0] stim_path, out_path;

  // The status outputs, not replayed: the equivalence proof covers them (hdl/tests/equivalence.rs).
  wire armed, window_done, set_accepted;

  window_unit #(.WIDTH(WIDTH), .HEIGHT(HEIGHT), .PIXEL_BITS(PIXEL_BITS)) dut(
      .clock(clock), .fval(fval), .lval(lval), .pixel(pixel),
      .coord_strobe(coord_strobe), .coord_data(coord_data), .coord_ready(coord_ready),
      .decimate(decimate), .pixel_strobe(pixel_strobe), .pixel_out(pixel_out),
      .coord_error(coord_error), .pixel_valid(pixel_valid), .reset(reset),
      .armed(armed), .window_done(window_done), .set_accepted(set_accepted));

  initial begin
    if (!$value$plusargs("stim=%s", stim_path) || !$value$plusargs("out=%s", out_path)) begin
      $display("replay_tb: usage: +stim=IN.txt +out=OUT.txt");
      $finish;
    end
    fin = $fopen(stim_path, "r");
    fout = $fopen(out_path, "w");
    if (fin == 0 || fout == 0) begin
      $display("replay_tb: cannot open %0s or %0s", stim_path, out_path);
      $finish;
    end
    fields = $fscanf(fin, "%h %h %h %h %h %h %h %h\n", f_fval, f_lval, f_valid, f_pixel,
                     f_reset, f_strobe, f_data, f_decimate);
    while (fields == 8) begin
      fval = f_fval[0]; lval = f_lval[0]; pixel_valid = f_valid[0];
      pixel = f_pixel[PIXEL_BITS-1:0]; reset = f_reset[0]; coord_strobe = f_strobe[0];
      coord_data = f_data[7:0]; decimate = f_decimate[0];
      #5 clock = 1;
      #1 $fwrite(fout, "%h %h %h %h\n", coord_ready, pixel_strobe, pixel_out, coord_error);
      #4 clock = 0;
      fields = $fscanf(fin, "%h %h %h %h %h %h %h %h\n", f_fval, f_lval, f_valid, f_pixel,
                       f_reset, f_strobe, f_data, f_decimate);
    end
    $fclose(fout);
    $finish;
  end
endmodule
`default_nettype wire

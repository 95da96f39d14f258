//! The D flip-flop both blocks are built from: rust-hdl's `DFF` widget with the same ports and
//! the same Verilog, and a simulation model that needs fewer settling passes, so the
//! direct-stepping driver runs about twice as fast (see `docs/window-logic.md`).
//!
//! rust-hdl settles a design by updating every block until no signal changes. Its `DFF` reports
//! a change of `clock` and `d` as well as `q`, and sees its clock edge one pass after the clock
//! reaches it, so each clock phase costs extra passes over the whole tree. `Reg` takes the edge
//! in the pass the clock arrives (sampling `d` before that pass's update of `d`, i.e. the value
//! settled before the edge) and reports only `q`, the one signal other logic reads.
use rust_hdl::core::prelude::*;

/// A positive-edge D flip-flop (Verilog identical to rust-hdl's `DFF`).
#[derive(Clone, Debug)]
pub struct Reg<T: Synth> {
    /// Next state, sampled on the rising edge.
    pub d: Signal<In, T>,
    /// State.
    pub q: Signal<Out, T>,
    /// Clock.
    pub clock: Signal<In, Clock>,
}

impl<T: Synth> Default for Reg<T> {
    fn default() -> Self {
        Self {
            d: Signal::default(),
            q: Signal::default(),
            clock: Signal::default(),
        }
    }
}

impl<T: Synth> Logic for Reg<T> {
    fn update(&mut self) {
        if self.clock.pos_edge() {
            self.q.next = self.d.val();
        }
    }

    fn connect(&mut self) {
        self.q.connect();
    }

    fn hdl(&self) -> Verilog {
        Verilog::Custom(format!(
            "\
initial begin
   q = {:x};
end

always @(posedge clock) begin
   q <= d;
end
      ",
            T::default().verilog()
        ))
    }

    fn timing(&self) -> Vec<TimingInfo> {
        vec![TimingInfo {
            name: "dff".into(),
            clock: "clock".into(),
            inputs: vec!["d".into()],
            outputs: vec!["q".into()],
        }]
    }
}

impl<T: Synth> Block for Reg<T> {
    fn connect_all(&mut self) {
        self.connect();
        self.d.connect_all();
        self.q.connect_all();
        self.clock.connect_all();
    }

    fn update_all(&mut self) {
        // The clock first, so the edge is taken in this pass; `d` after sampling, so the
        // sample is the value settled before the edge.
        self.clock.update_all();
        self.update();
        self.d.update_all();
        self.q.update_all();
    }

    fn has_changed(&self) -> bool {
        self.q.has_changed()
    }

    fn accept(&self, name: &str, probe: &mut dyn Probe) {
        probe.visit_start_scope(name, self);
        self.d.accept("d", probe);
        self.q.accept("q", probe);
        self.clock.accept("clock", probe);
        probe.visit_end_scope(name, self);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rust_hdl::prelude::*;

    /// The logic under test, generic in its flip-flop: a counter enabled by the input and a
    /// two-stage pipeline of a value computed from it, one level down so the clock reaches the
    /// flip-flops through a sub-block, as in `WindowUnit`.
    #[derive(LogicBlock, Default)]
    struct Top<F: Flop> {
        clock: Signal<In, Clock>,
        en: Signal<In, Bit>,
        x: Signal<In, Bits<8>>,
        out: Signal<Out, Bits<8>>,
        inner: Inner<F>,
    }

    impl<F: Flop> Logic for Top<F> {
        fn update(&mut self) {
            self.inner.clock.next = self.clock.val();
            self.inner.en.next = self.en.val();
            self.inner.x.next = self.x.val();
            self.out.next = self.inner.out.val();
        }
    }

    #[derive(LogicBlock, Default)]
    struct Inner<F: Flop> {
        clock: Signal<In, Clock>,
        en: Signal<In, Bit>,
        x: Signal<In, Bits<8>>,
        out: Signal<Out, Bits<8>>,
        sum: Signal<Local, Bits<8>>,
        count: F,
        stage1: F,
        stage2: F,
    }

    impl<F: Flop> Logic for Inner<F> {
        fn update(&mut self) {
            let clock = self.clock.val();
            for f in [&mut self.count, &mut self.stage1, &mut self.stage2] {
                f.clock().next = clock;
            }
            let (count, s1, s2) = (self.count.q(), self.stage1.q(), self.stage2.q());
            self.count.d().next = if self.en.val() { count + 1 } else { count };
            self.sum.next = self.x.val() + count;
            self.stage1.d().next = self.sum.val();
            self.stage2.d().next = s1;
            self.out.next = s2 ^ count;
        }
    }

    /// What `Inner` needs of a flip-flop.
    trait Flop: Block + Default {
        fn clock(&mut self) -> &mut Signal<In, Clock>;
        fn d(&mut self) -> &mut Signal<In, Bits<8>>;
        fn q(&self) -> Bits<8>;
    }

    macro_rules! flop {
        ($t:ty) => {
            impl Flop for $t {
                fn clock(&mut self) -> &mut Signal<In, Clock> {
                    &mut self.clock
                }
                fn d(&mut self) -> &mut Signal<In, Bits<8>> {
                    &mut self.d
                }
                fn q(&self) -> Bits<8> {
                    self.q.val()
                }
            }
        };
    }
    flop!(Reg<Bits<8>>);
    flop!(DFF<Bits<8>>);

    fn clock_in<F: Flop>(top: &mut Top<F>, en: bool, x: u64) -> Bits<8> {
        top.en.next = en;
        top.x.next = x.into();
        top.clock.next = false.into();
        assert!(simulate(top, 64));
        top.clock.next = true.into();
        assert!(simulate(top, 64));
        top.out.val()
    }

    #[test]
    fn reg_matches_rust_hdl_dff_clock_for_clock() {
        // Reference: the same logic on rust-hdl's own DFF, each design settled on its own by
        // rust-hdl's `simulate`.
        let (mut ours, mut theirs) = (
            Top::<Reg<Bits<8>>>::default(),
            Top::<DFF<Bits<8>>>::default(),
        );
        ours.connect_all();
        theirs.connect_all();
        let mut seed = 0x2545_f491_u32;
        let mut seen = std::collections::BTreeSet::new();
        for _ in 0..2_000 {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            let (en, x) = (seed & 1 == 1, (seed >> 8) as u64 & 0xff);
            let out = clock_in(&mut ours, en, x);
            assert_eq!(out, clock_in(&mut theirs, en, x));
            seen.insert(out.index());
        }
        // The comparison saw the logic move, not two idle blocks.
        assert!(seen.len() > 100, "{}", seen.len());
    }
}

//! How big each experiment is: the full run reproduces the thesis at its
//! 800×600 frame; the quick run keeps every experiment but shrinks frames
//! and the budgets whose cost grows exponentially, so that it finishes in
//! about a minute and can be a test.

/// Frame sizes and budgets of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct Plan {
    pub quick: bool,
    /// Frame of the ray-count tables (Tables 4.1, 4.2, 4.4–4.6, supersampling).
    pub table: (u32, u32),
    /// Frame of Table 4.3 (mutual reflection), whose largest budget costs
    /// more than all the other tables together.
    pub mirror_frame: (u32, u32),
    /// Reflection budgets of Table 4.3 (the thesis: 1, 4, 32).
    pub mirror_rays: [u32; 3],
    /// Reflection and shadow budget of the last row of Table 4.4 (thesis: 32).
    pub heavy_metric_rays: u32,
    /// Frame of the figures; each figure renders a crop of it.
    pub figure: (u32, u32),
    /// Frame and budgets of the metric sweep (reduction against budget).
    pub sweep: (u32, u32),
    pub sweep_shadow: Vec<u32>,
    pub sweep_reflection: Vec<u32>,
    /// Frame of the convergence study (a crop of it is rendered), its ray
    /// counts, seeds per count and the reference's rays.
    pub convergence: (u32, u32),
    pub conv_counts: Vec<u32>,
    pub conv_seeds: u32,
    pub conv_reference: u32,
}

impl Plan {
    pub fn new(quick: bool) -> Plan {
        if quick {
            Plan::quick()
        } else {
            Plan::full()
        }
    }

    fn full() -> Plan {
        Plan {
            quick: false,
            table: (800, 600),
            mirror_frame: (400, 300),
            mirror_rays: [1, 4, 32],
            heavy_metric_rays: 32,
            figure: (800, 600),
            sweep: (400, 300),
            sweep_shadow: vec![4, 8, 16, 32, 64],
            sweep_reflection: vec![4, 8, 16],
            convergence: (400, 300),
            conv_counts: vec![4, 9, 16, 36, 64],
            conv_seeds: 3,
            conv_reference: 1024,
        }
    }

    fn quick() -> Plan {
        Plan {
            quick: true,
            table: (160, 120),
            mirror_frame: (160, 120),
            mirror_rays: [1, 4, 8],
            heavy_metric_rays: 8,
            figure: (320, 240),
            sweep: (160, 120),
            sweep_shadow: vec![4, 8, 16, 32],
            sweep_reflection: vec![4, 8],
            convergence: (160, 120),
            conv_counts: vec![4, 9, 16, 36, 64],
            conv_seeds: 1,
            conv_reference: 256,
        }
    }

    /// Sentences for the report on how this run differs from the thesis.
    pub fn deviations(&self) -> Vec<String> {
        let mut out = Vec::new();
        let (w, h) = self.table;
        if (w, h) != (800, 600) {
            out.push(format!(
                "Quick run: the tables are rendered at {w}×{h}; the column \"at 800×600\" scales \
                 each count by the pixel ratio ({:.0}×) for comparison with the thesis.",
                800.0 * 600.0 / f64::from(w * h)
            ));
        }
        let (mw, mh) = self.mirror_frame;
        if (mw, mh) != self.table {
            out.push(format!(
                "Table 4.3 (mutual reflection) is rendered at {mw}×{mh} and scaled to 800×600 by \
                 the pixel ratio: its 32-ray rows trace billions of rays at the full frame."
            ));
        }
        if self.mirror_rays[2] != 32 {
            out.push(format!(
                "Quick run: Table 4.3 uses {} instead of 32 reflection rays, and the last row of \
                 Table 4.4 uses {0}r {0}s 4x instead of 32r 32s 4x (their cost grows with the cube \
                 of the budget).",
                self.mirror_rays[2]
            ));
        }
        if self.quick {
            out.push(format!(
                "Quick run: figures are crops of a {}×{} frame; the convergence study uses {} seed \
                 and a {}-ray reference.",
                self.figure.0, self.figure.1, self.conv_seeds, self.conv_reference
            ));
        }
        out
    }
}

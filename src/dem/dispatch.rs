//! CPU feature dispatch: the engine's step is compiled once per instruction set and the
//! widest one this CPU runs is chosen at run time. Every copy performs the same IEEE-754
//! operations in the same order (Rust never fuses a multiply and an add unless asked), so
//! all give the same bits (`tests/suite/dispatch.rs`).

/// An instruction set the engine's step is compiled for (see
/// [`super::engine::Simulation::step`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[doc(hidden)]
pub enum Isa {
    /// The baseline of the target (x86-64: SSE2).
    Portable,
    /// AVX2 and FMA.
    Avx2,
    /// AVX-512F and AVX-512VL (with AVX2 and FMA).
    Avx512,
}

impl Isa {
    /// Every variant, baseline first.
    pub const ALL: [Isa; 3] = [Isa::Portable, Isa::Avx2, Isa::Avx512];

    /// Whether this CPU runs the variant.
    pub fn available(self) -> bool {
        match self {
            Isa::Portable => true,
            #[cfg(target_arch = "x86_64")]
            Isa::Avx2 => std::is_x86_feature_detected!("avx2") && std::is_x86_feature_detected!("fma"),
            #[cfg(target_arch = "x86_64")]
            Isa::Avx512 => {
                Isa::Avx2.available()
                    && std::is_x86_feature_detected!("avx512f")
                    && std::is_x86_feature_detected!("avx512vl")
            }
            #[cfg(not(target_arch = "x86_64"))]
            _ => false,
        }
    }

    /// The widest variant this CPU runs (detected once per process).
    pub fn best() -> Isa {
        static BEST: std::sync::OnceLock<Isa> = std::sync::OnceLock::new();
        *BEST.get_or_init(|| {
            if Isa::Avx512.available() {
                Isa::Avx512
            } else if Isa::Avx2.available() {
                Isa::Avx2
            } else {
                Isa::Portable
            }
        })
    }
}

//! A body specialised on the joint count (a code-generation helper of the connection's hot
//! loops and of their callers).

/// `body(n)` with `n` a constant for two to seven joints (the loops of the inlined body unrolled,
/// their bounds checks gone; the same operations in the same order, so the same bits), else
/// with `n` as it comes.
macro_rules! specialised {
    ($n:expr, |$k:ident| $body:expr) => {
        match $n {
            2 => {
                let $k = 2;
                $body
            }
            3 => {
                let $k = 3;
                $body
            }
            4 => {
                let $k = 4;
                $body
            }
            5 => {
                let $k = 5;
                $body
            }
            6 => {
                let $k = 6;
                $body
            }
            7 => {
                let $k = 7;
                $body
            }
            $k => $body,
        }
    };
}
pub(crate) use specialised;

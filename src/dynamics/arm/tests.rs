//! Tests of the n-link dynamics.

use super::*;

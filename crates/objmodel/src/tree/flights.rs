//! The flights' centres of mass in the tree: each demonstration's flights that determined the
//! point that fell with gravity ([`crate::flight`]), kept per demonstration so that learning
//! more tosses later pools them all, and pooled ([`crate::shared_com`]) into the tree's centre
//! of mass (`tree/com.rs`).
//!
//! Only direct demonstrations' flights count (an object on a palm does not fly), and only the
//! flights' own points: a thrown object that never rests on a face still tells where its
//! centre of mass is, which is what a simulation of it needs first.

use super::flight_com::FlightCom;
use super::Tree;
use crate::classify::Classification;
use crate::flight::ComEstimate;
use crate::shared_com::{shared_com, SharedCom};

impl Tree {
    /// Keep the flights' centres of mass of the demonstration `c`, under its name in the tree.
    pub(super) fn add_flights(&mut self, demo: &str, c: &Classification) {
        self.flights.extend(
            c.flight_coms_taught()
                .iter()
                .map(|e| FlightCom::of(demo, e)),
        );
    }

    /// The centre of mass the tree's flights agree on ([`shared_com`]), if they do.
    pub fn flights_com(&self) -> Option<SharedCom> {
        let mut names: Vec<&str> = Vec::new();
        let flights: Vec<(usize, ComEstimate)> = self
            .flights
            .iter()
            .map(|f| {
                let k = names.iter().position(|n| *n == f.demo).unwrap_or_else(|| {
                    names.push(&f.demo);
                    names.len() - 1
                });
                (k, f.estimate())
            })
            .collect();
        shared_com(&flights)
    }
}

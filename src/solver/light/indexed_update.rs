//! Parallel updates of a slice at a list of ascending indices: a shot's
//! closed zone lists its vertices and elements in ascending order, so the
//! slice splits into disjoint parts along the list, and each part is
//! updated on its own thread. The result does not depend on the split:
//! each item is written once, by `update`, from what it reads.

/// Below this many indices a part is updated on one thread: handing work
/// to rayon costs tens of microseconds, as much as a few thousand updates.
pub(crate) const SERIAL_PART: usize = 8192;

/// Calls `update(k, item)` for every `k` with `item = &mut data[indices[k]]`,
/// in parallel. `indices` must be strictly ascending and within `data`
/// (a zone's member list); out-of-range indices are skipped.
pub(crate) fn par_update_at<T, F>(data: &mut [T], indices: &[u32], update: &F)
where
    T: Send,
    F: Fn(usize, &mut T) + Sync,
{
    update_part(data, 0, indices, 0, update);
}

/// `par_update_at` on `data`, which starts at index `offset` of the whole
/// slice, for `indices`, which start at position `first` of the whole list.
fn update_part<T, F>(data: &mut [T], offset: usize, indices: &[u32], first: usize, update: &F)
where
    T: Send,
    F: Fn(usize, &mut T) + Sync,
{
    if indices.len() <= SERIAL_PART {
        for (k, &i) in indices.iter().enumerate() {
            if let Some(item) = (i as usize)
                .checked_sub(offset)
                .and_then(|i| data.get_mut(i))
            {
                update(first + k, item);
            }
        }
        return;
    }
    let middle = indices.len() / 2;
    let split = (indices[middle] as usize)
        .saturating_sub(offset)
        .min(data.len());
    let (low, high) = data.split_at_mut(split);
    let (low_indices, high_indices) = indices.split_at(middle);
    rayon::join(
        || update_part(low, offset, low_indices, first, update),
        || update_part(high, offset + split, high_indices, first + middle, update),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every listed item, and only those, is updated once with its position
    /// in the list, whatever the list's size and gaps.
    #[test]
    fn updates_exactly_the_listed_items() {
        for (len, step) in [(0, 1), (10, 3), (100_000, 1), (100_000, 7), (50_000, 2)] {
            let indices: Vec<u32> = (0..len as u32).step_by(step).collect();
            let mut data = vec![(0_usize, 0_u32); len];
            par_update_at(&mut data, &indices, &|k, item| {
                item.0 = k;
                item.1 += 1;
            });
            for (i, &(k, count)) in data.iter().enumerate() {
                if i % step == 0 {
                    assert_eq!((k, count), (i / step, 1), "item {i}");
                } else {
                    assert_eq!(count, 0, "item {i}");
                }
            }
        }
    }

    /// Indices past the slice's end are skipped, not a panic.
    #[test]
    fn skips_indices_out_of_range() {
        let indices: Vec<u32> = (0..10_000).map(|i| i * 2).collect();
        let mut data = vec![0_u32; 5_000];
        par_update_at(&mut data, &indices, &|_, item| *item += 1);
        assert_eq!(data.iter().sum::<u32>(), 2_500);
    }
}

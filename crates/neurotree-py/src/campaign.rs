//! `neurotree.Campaign`: a campaign file (the TOML `neurotree campaign run` reads) run from
//! Python, each variant in Rust with the GIL released; the package's `campaigns.py` sends
//! shards to Ray.

use std::path::{Path, PathBuf};

use neurotree_cli::campaign::{self, Campaign, Results};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// A campaign, read and checked.
#[pyclass(name = "Campaign", module = "neurotree._native", frozen)]
pub(crate) struct PyCampaign {
    campaign: Campaign,
}

#[pymethods]
impl PyCampaign {
    /// Reads the campaign file at `path`; a bad file raises ValueError naming its line and
    /// column.
    #[staticmethod]
    fn load(path: PathBuf) -> PyResult<Self> {
        Campaign::load(&path)
            .map(|campaign| Self { campaign })
            .map_err(PyValueError::new_err)
    }

    /// Reads `text` as the campaign file `file` (a tree it names is relative to `file`).
    #[staticmethod]
    fn parse(text: &str, file: PathBuf) -> PyResult<Self> {
        Campaign::parse(text, &file)
            .map(|campaign| Self { campaign })
            .map_err(PyValueError::new_err)
    }

    /// Its name.
    #[getter]
    fn name(&self) -> String {
        self.campaign.name.clone()
    }

    /// The file's text.
    #[getter]
    fn text(&self) -> String {
        self.campaign.text.clone()
    }

    /// Where the file is.
    #[getter]
    fn file(&self) -> PathBuf {
        self.campaign.file.clone()
    }

    /// How many variants it has.
    #[getter]
    fn variants(&self) -> u64 {
        self.campaign.variants()
    }

    /// The variants of the first `limit` (all when None) that the results file `db` does
    /// not hold yet; ValueError if it holds some and `resume` is false.
    #[pyo3(signature = (db, limit = None, resume = false))]
    fn todo(&self, db: PathBuf, limit: Option<u64>, resume: bool) -> PyResult<Vec<u64>> {
        let results = Results::open(&db).map_err(PyValueError::new_err)?;
        let selected = campaign::selection(self.campaign.variants(), limit, None);
        self.campaign
            .todo(&results, selected, resume)
            .map(|(todo, _)| todo)
            .map_err(PyValueError::new_err)
    }

    /// Runs `variants` into the results file `db` on `threads` threads (0: every core),
    /// with the GIL released; the number of them that succeeded.
    #[pyo3(signature = (db, variants, threads = 0))]
    fn run_variants(
        &self,
        py: Python<'_>,
        db: PathBuf,
        variants: Vec<u64>,
        threads: usize,
    ) -> PyResult<u64> {
        py.allow_threads(|| {
            let results = Results::open(&db)?;
            results.claim(&self.campaign)?;
            let mut succeeded = 0;
            self.campaign
                .run_into(&results, &variants, threads, &mut |row| {
                    succeeded += u64::from(row.outcome == "SUCCESS");
                })?;
            Ok::<_, String>(succeeded)
        })
        .map_err(PyValueError::new_err)
    }
}

/// Adds the rows of the results files `sources` to `db`; the number added.
#[pyfunction]
pub(crate) fn _merge_campaign_results(
    py: Python<'_>,
    sources: Vec<PathBuf>,
    db: PathBuf,
) -> PyResult<usize> {
    py.allow_threads(|| {
        let sources: Vec<&Path> = sources.iter().map(PathBuf::as_path).collect();
        campaign::merge(&sources, &db)
    })
    .map_err(PyValueError::new_err)
}

//! A Parquet table read back (a shard's partial result, a result folder's tables): its columns by
//! type, each error naming the file.

use std::path::Path;

use polars::prelude::*;

use crate::error::{Error, Result};

pub(crate) struct Table {
    pub(crate) df: DataFrame,
    shown: String,
}

impl Table {
    pub(crate) fn read(dir: &Path, file: &str) -> Result<Self> {
        let path = dir.join(file);
        let f = std::fs::File::open(&path).map_err(|e| Error::io(&path, e))?;
        let shown = path.display().to_string();
        let df = ParquetReader::new(f).finish().map_err(|e| Error::invalid(&shown, e.to_string()))?;
        Ok(Table { df, shown })
    }
    pub(crate) fn bad(&self, why: impl std::fmt::Display) -> Error {
        Error::invalid(&self.shown, why.to_string())
    }
    pub(crate) fn column(&self, name: &str) -> Result<&Column> {
        self.df.column(name).map_err(|e| self.bad(e))
    }
    /// Columns without nulls, as a shard writes them.
    pub(crate) fn u32s(&self, name: &str) -> Result<Vec<u32>> {
        Ok(self.column(name)?.u32().map_err(|e| self.bad(e))?.into_no_null_iter().collect())
    }
    pub(crate) fn u64s(&self, name: &str) -> Result<Vec<u64>> {
        Ok(self.column(name)?.u64().map_err(|e| self.bad(e))?.into_no_null_iter().collect())
    }
    pub(crate) fn f64s(&self, name: &str) -> Result<Vec<f64>> {
        Ok(self.column(name)?.f64().map_err(|e| self.bad(e))?.into_no_null_iter().collect())
    }
    pub(crate) fn has(&self, name: &str) -> bool {
        self.df.column(name).is_ok()
    }
    pub(crate) fn cast(&self, name: &str, dtype: &DataType) -> Result<Series> {
        self.column(name)?.as_materialized_series().cast(dtype).map_err(|e| self.bad(format!("column `{name}`: {e}")))
    }
    pub(crate) fn opt_f64s(&self, name: &str) -> Result<Vec<Option<f64>>> {
        let s = self.cast(name, &DataType::Float64)?;
        Ok(s.f64().map_err(|e| self.bad(e))?.iter().collect())
    }
    pub(crate) fn opt_u64s(&self, name: &str) -> Result<Vec<Option<u64>>> {
        let s = self.cast(name, &DataType::UInt64)?;
        Ok(s.u64().map_err(|e| self.bad(e))?.iter().collect())
    }
    pub(crate) fn bools(&self, name: &str) -> Result<Vec<Option<bool>>> {
        let s = self.cast(name, &DataType::Boolean)?;
        Ok(s.bool().map_err(|e| self.bad(e))?.iter().collect())
    }
    pub(crate) fn strs(&self, name: &str) -> Result<Vec<Option<String>>> {
        let s = self.cast(name, &DataType::String)?;
        Ok(s.str().map_err(|e| self.bad(e))?.iter().map(|v| v.map(str::to_string)).collect())
    }
    pub(crate) fn required(&self, name: &str) -> Result<Vec<String>> {
        self.strs(name)?
            .into_iter()
            .enumerate()
            .map(|(i, v)| v.ok_or_else(|| self.bad(format!("row {i}: `{name}` is null"))))
            .collect()
    }
    pub(crate) fn height(&self) -> usize {
        self.df.height()
    }
}

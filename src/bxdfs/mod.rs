pub mod hair;
